#include "phase_limits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace dmgplace::runtime::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A joint moving slower than this per unit of path length takes no part in the s_ddot bounds:
// its acceleration is then its curvature term alone, which the limit curve covers.
constexpr double kStill = 1e-12;
constexpr double kRounding = 1e-9;

// |g| <= bound on [0, 1] for the parabola through g(0) = g0, g(1/2) = gm, g(1) = g1.
bool parabola_within(double g0, double gm, double g1, double bound) {
  // Through nodes 0, 1/2, 1 a parabola stays within 1.25 times its largest node value (the
  // nodes' Lebesgue constant); 1.3 also covers the rounding of the extremum computed below, so
  // these shortcuts give the same answer as the full test.
  const double largest = std::max({std::abs(g0), std::abs(gm), std::abs(g1)});
  if (largest > bound) return false;
  if (1.3 * largest <= bound) return true;
  const double b = -3 * g0 + 4 * gm - g1, c = 2 * g0 - 4 * gm + 2 * g1;
  double hi = std::max({g0, gm, g1}), lo = std::min({g0, gm, g1});
  if (c != 0) {
    const double x = -b / (2 * c);
    if (x > 0 && x < 1) {
      const double top = g0 + x * (b + c * x);
      hi = std::max(hi, top), lo = std::min(lo, top);
    }
  }
  return hi <= bound && -lo <= bound;
}

}  // namespace

PhaseLimits::PhaseLimits(const BlendedPath& path, const Eigen::VectorXd& max_velocity,
                         const Eigen::VectorXd& max_acceleration, double margin)
    : path_(path), n_(max_velocity.size()), vmax_(max_velocity), amax_(max_acceleration),
      veff_(max_velocity * (1 - margin)), aeff_(max_acceleration * (1 - margin)),
      cache_store_(std::size_t(2 * kCached * n_)), acc_(std::size_t(3 * n_)), vel2_(std::size_t(3 * n_)) {
  for (int i = 0; i < kCached; ++i) {
    cache_[i].dq = cache_store_.data() + 2 * i * n_;
    cache_[i].ddq = cache_[i].dq + n_;
  }
}

PhaseLimits::Point& PhaseLimits::load(int piece, double s) const {
  for (Point& p : cache_)
    if (p.s == s && p.piece == piece) return p;
  Point& p = cache_[cache_next_];
  cache_next_ = (cache_next_ + 1) % kCached;
  path_.derivatives(piece, s, p.dq, p.ddq);
  p.piece = piece, p.s = s;
  p.curved = std::any_of(p.ddq, p.ddq + n_, [](double x) { return x != 0.0; });
  p.has_max_u = p.has_velocity_max_u = false;
  return p;
}

double PhaseLimits::velocity_max_u(Point& p) const {
  if (p.has_velocity_max_u) return p.velocity_max_u;
  double u = kInf;
  for (Eigen::Index j = 0; j < n_; ++j) {
    const double d = std::abs(p.dq[j]);
    if (d > kStill) u = std::min(u, (veff_[j] / d) * (veff_[j] / d));
  }
  p.has_velocity_max_u = true;
  return p.velocity_max_u = u;
}

double PhaseLimits::max_u(Point& p) const {
  if (p.has_max_u) return p.max_u;
  double u = velocity_max_u(p);
  // On a line any speed leaves some s_ddot. Otherwise joints i and j each allow an interval of
  // s_ddot; both are non-empty and, in one dimension, all intervals share a point iff every pair
  // does. Pair (i, j) overlaps iff u |ddq_i dq_j - ddq_j dq_i| <= a_i |dq_j| + a_j |dq_i| (a
  // joint at rest, dq_i = 0, gives u |ddq_i| <= a_i through any partner).
  const double *dq = p.dq, *ddq = p.ddq;
  for (Eigen::Index i = 0; p.curved && i < n_; ++i)
    for (Eigen::Index j = i + 1; j < n_; ++j) {
      const double den = std::abs(ddq[i] * dq[j] - ddq[j] * dq[i]);
      const double num = aeff_[i] * std::abs(dq[j]) + aeff_[j] * std::abs(dq[i]);
      // Divides only where the quotient may be below u: the product's rounding is far below the
      // 1e-12 allowance, so the minimum is the same as dividing every pair.
      if (den > 0 && num <= u * den * (1 + 1e-12)) u = std::min(u, num / den);
    }
  p.has_max_u = true;
  return p.max_u = u;
}

double PhaseLimits::max_u(int piece, double s) const { return max_u(load(piece, s)); }

double PhaseLimits::velocity_max_u(int piece, double s) const { return velocity_max_u(load(piece, s)); }

// The difference quotient's ends around s: one-sided (side != 0) or central, within the piece,
// not straddling a corner of the curve (a joint turn) other than s itself.
std::pair<double, double> PhaseLimits::slope_interval(int piece, double s, int side) const {
  const PathPiece& p = path_.piece(piece);
  const double at = 4 * std::numeric_limits<double>::epsilon() * std::abs(s);
  double room_left = s - p.start, room_right = p.end() - s;
  for (double t : p.joint_turns) {
    const double d = p.start + t - s;
    if (d > at) room_right = std::min(room_right, d);
    if (d < -at) room_left = std::min(room_left, -d);
  }
  const double h = std::max(1e-7 * std::min(p.radius, p.length), 1e3 * std::numeric_limits<double>::epsilon() * s);
  const double left = side > 0 || room_left <= at ? 0.0 : std::min(h, room_left / 2);
  const double right = side < 0 || room_right <= at ? 0.0 : std::min(h, room_right / 2);
  if (left + right > 0) return {s - left, s + right};
  return {s - std::min(h, room_left / 2), s + std::min(h, room_right / 2)};  // no room on that side
}

double PhaseLimits::max_u_slope(int piece, double s, int side, bool velocity_only) const {
  if (!path_.piece(piece).is_arc()) return 0;  // the curve is flat along a line
  const auto [a, b] = slope_interval(piece, s, side);
  const auto curve = [&](double x) { return velocity_only ? velocity_max_u(piece, x) : max_u(piece, x); };
  return (curve(b) - curve(a)) / (b - a);
}

AccelRange PhaseLimits::side_accel_range(int piece, double s, int side) const {
  double at = s;
  if (side != 0 && path_.piece(piece).is_arc()) {
    const auto [a, b] = slope_interval(piece, s, side);
    at = side < 0 ? a : b;
  }
  return accel_range(piece, at, max_u(piece, at));
}

AccelRange PhaseLimits::reach_range(int piece, double s, double u_from, double k) const {
  return {reach_min(piece, s, u_from, k), reach_max(piece, s, u_from, k)};
}

double PhaseLimits::reach_bound(int piece, double s, double u_from, double k, bool upper) const {
  const Point& p = load(piece, s);
  double bound = upper ? kInf : -kInf;
  // Joint j: dq_j a + ddq_j (u_from + 2 a k) in [-a_j, a_j], a_j with half the rounding allowance
  // within_limits grants: near a joint turn (dq_j ~ 0) the bound's own rounding error is
  // amplified by 1 / dq_j, and the allowance absorbs it.
  for (Eigen::Index j = 0; j < n_; ++j) {
    const double c = p.dq[j] + 2 * k * p.ddq[j], offset = p.ddq[j] * u_from, limit = aeff_[j] * (1 + 0.5 * kRounding);
    if (std::abs(c) <= kStill) {
      if (k != 0 && std::abs(offset) > limit) return upper ? -kInf : kInf;  // no a fits
      continue;
    }
    // Dividing by c < 0 swaps which end of [-a_j, a_j] bounds a from above.
    const double a = ((upper == (c > 0)) ? limit : -limit) - offset;
    bound = upper ? std::min(bound, a / c) : std::max(bound, a / c);
  }
  if (!upper && k > 0) bound = std::max(bound, -u_from / (2 * k));  // the speed reached stays real
  if (upper && k < 0) bound = std::min(bound, u_from / (-2 * k));
  return bound;
}

bool PhaseLimits::within_limits(int piece, double s, double u, double a, bool shrunk) const {
  const Point& p = load(piece, s);
  const double* vmax = shrunk ? veff_.data() : vmax_.data();
  const double* amax = shrunk ? aeff_.data() : amax_.data();
  const double sd = std::sqrt(std::max(u, 0.0));
  for (Eigen::Index j = 0; j < n_; ++j) {
    if (std::abs(p.dq[j]) * sd > vmax[j] * (1 + kRounding)) return false;
    if (std::abs(p.dq[j] * a + p.ddq[j] * u) > amax[j] * (1 + kRounding)) return false;
  }
  return true;
}

bool PhaseLimits::step_within_limits(int piece, double s0, double u0, double s1, double u1, double a) const {
  const double s[3] = {s0, 0.5 * (s0 + s1), s1}, u[3] = {u0, 0.5 * (u0 + u1), u1};
  for (int k = 0; k < 3; ++k) {
    const Point& p = load(piece, s[k]);
    const double u_real = std::max(u[k], 0.0);
    for (Eigen::Index j = 0; j < n_; ++j) {
      acc_[std::size_t(3 * j + k)] = p.dq[j] * a + p.ddq[j] * u[k];
      vel2_[std::size_t(3 * j + k)] = p.dq[j] * p.dq[j] * u_real;
    }
  }
  for (Eigen::Index j = 0; j < n_; ++j) {
    const double *acc = &acc_[std::size_t(3 * j)], *vel2 = &vel2_[std::size_t(3 * j)];
    if (!parabola_within(acc[0], acc[1], acc[2], amax_[j] * (1 + kRounding)) ||
        !parabola_within(vel2[0], vel2[1], vel2[2], vmax_[j] * vmax_[j] * (1 + 2 * kRounding)))
      return false;
  }
  return true;
}

}  // namespace dmgplace::runtime::detail
