#include "dmgplace/runtime/collision/displacement_bound.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dmgplace::runtime {

void BallMotion::add_revolute(const Eigen::Vector3d& axis, const Eigen::Vector3d& origin, double rate, double reach) {
  const Eigen::Vector3d arm = axis.cross(center_ - origin);  // the center's velocity per unit of rate
  add_revolute_arm(axis, arm, arm.norm(), rate, reach);
}

void BallMotion::add_revolute_arm(const Eigen::Vector3d& axis, const Eigen::Vector3d& arm, double arm_norm, double rate,
                                  double reach) {
  const double au = std::abs(rate);
  b_.reach_speed += au * reach;
  frame_turn_ += au;
  const double r = arm_norm + radius_;
  linear_ += rate * arm;
  angular_ += rate * axis;
  b_.local_speed += au * r;
  b_.second_order += au * frame_turn_ * r;
  b_.turn_rate += au;
}

void BallMotion::add_prismatic(const Eigen::Vector3d& axis, double rate, double reach) {
  const double au = std::abs(rate);
  b_.reach_speed += au * reach;
  linear_ += rate * axis;
  b_.local_speed += au;
  b_.second_order += au * frame_turn_;  // the axis turns with the joints above
}

DisplacementBound BallMotion::bound() const {
  DisplacementBound b = b_;
  b.first_order = linear_.norm() + angular_.norm() * radius_;
  return b;
}

void DisplacementBound::add(const DisplacementBound& o) {
  // Sums bound the sum of the displacements; G and the Taylor remainder grow with the turn rate,
  // so the larger one serves both.
  reach_speed += o.reach_speed;
  local_speed += o.local_speed;
  first_order += o.first_order;
  second_order += o.second_order;
  turn_rate = std::max(turn_rate, o.turn_rate);
}

double DisplacementBound::time_to_move(double clearance, double enough) const {
  if (!(clearance > 0)) return 0.0;  // (the Gronwall form's Pade factor is meaningless below -1)
  const double inf = std::numeric_limits<double>::infinity();
  const double t_static = reach_speed > 0 ? clearance / reach_speed : inf;
  double t_local = inf;
  if (local_speed > 0) {
    if (turn_rate > 1e-12) {
      // Gronwall's log1p(c w / v) / w, first from log1p's Pade form (log1p_ratio_lower), exact to
      // 2e-4 below x = 0.5, where most certificates are: the logarithm only past that.
      const double x = clearance * turn_rate / local_speed;
      t_local = clearance / local_speed * log1p_ratio_lower(x);
      if (x > 0.5 && std::max(t_static, t_local) < enough) t_local = std::log1p(x) / turn_rate;
    } else {
      t_local = clearance / local_speed;
    }
  }
  const double best = std::max(t_static, t_local);
  if (best >= enough) return best;
  // The Taylor bound is at least first_order * t: it cannot last past clearance / first_order.
  if (!(first_order * best < clearance)) return best;
  return std::max(best, taylor_time(clearance));
}

double DisplacementBound::taylor_time(double clearance) const {
  const double a = first_order, s = second_order, v = local_speed, w = turn_rate, c = clearance;
  if (!(c > 0)) return 0.0;
  const bool turns = w > 1e-12;
  // Start above the root: by then one term alone has reached the clearance (the exponential
  // remainder is at least v w t^2 / 2).
  double t0 = std::numeric_limits<double>::infinity();
  if (a > 0) t0 = c / a;
  if (s > 0) t0 = std::min(t0, std::sqrt(2 * c / s));
  if (turns && v > 0) t0 = std::min(t0, std::sqrt(2 * c / (v * w)));
  if (!std::isfinite(t0)) return t0;  // nothing moves
  // On [0, t0] the remainder v / w (e^x - 1 - x), x = w t, is at most v / w (x^2 / 2 + x^3 e^x0 / 6)
  // (the series from x^3 on is at most x^3 / 6 times e^x), and e^x0 <= 1 / (1 - x0) below 1: a
  // cubic g above the bound, convex, g(0) = 0, with no exponential to evaluate.
  const double x0 = w * t0;
  const double e0 = !turns ? 0.0 : x0 < 0.5 ? 1.0 / (1.0 - x0) : std::exp(x0);
  const double k2 = 0.5 * (s + v * w), k3 = v * w * w * e0 / 6.0;
  auto g = [&](double t) { return t * (a + t * (k2 + t * k3)); };
  auto dg = [&](double t) { return a + t * (2 * k2 + 3 * t * k3); };
  double t = t0;
  for (int k = 0; k < 2; ++k) t -= (g(t) - c) / dg(t);  // Newton from above stays above (g is convex)
  // g lies under its chord from 0, so g(t c / g(t)) <= c; below t0 the true bound is under g.
  const double gt = g(t);
  return gt > c ? t * (c / gt) : t;
}

double DisplacementBound::displacement(double t) const {
  double d = reach_speed * t;
  if (turn_rate > 1e-12) {
    const double x = turn_rate * t;
    d = std::min(d, local_speed / turn_rate * std::expm1(x));
    d = std::min(d, first_order * t + 0.5 * second_order * t * t + local_speed / turn_rate * (std::expm1(x) - x));
  } else {
    d = std::min({d, local_speed * t, first_order * t + 0.5 * second_order * t * t});
  }
  return d;
}

}  // namespace dmgplace::runtime
