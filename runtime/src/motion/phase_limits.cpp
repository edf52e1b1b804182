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
    : path_(path),
      vmax_(max_velocity),
      amax_(max_acceleration),
      veff_(max_velocity * (1 - margin)),
      aeff_(max_acceleration * (1 - margin)) {}

void PhaseLimits::load(int piece, double s) const {
  if (piece == loaded_piece_ && s == loaded_s_) return;  // the integration asks about one state repeatedly
  path_.derivatives(piece, s, dq_, ddq_);
  loaded_piece_ = piece, loaded_s_ = s;
}

double PhaseLimits::loaded_velocity_max_u() const {
  double u = kInf;
  for (Eigen::Index j = 0; j < dq_.size(); ++j) {
    const double d = std::abs(dq_[j]);
    if (d > kStill) u = std::min(u, (veff_[j] / d) * (veff_[j] / d));
  }
  return u;
}

double PhaseLimits::loaded_max_u() const {
  const Eigen::Index n = dq_.size();
  double u = loaded_velocity_max_u();
  if (ddq_.isZero(0.0)) return u;  // a line: any speed leaves some s_ddot
  // Joints i and j each allow an interval of s_ddot; both are non-empty and, in one dimension,
  // all intervals share a point iff every pair does. Pair (i, j) overlaps iff
  // u |ddq_i dq_j - ddq_j dq_i| <= a_i |dq_j| + a_j |dq_i| (a joint at rest, dq_i = 0, gives
  // u |ddq_i| <= a_i through any partner).
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const double den = std::abs(ddq_[i] * dq_[j] - ddq_[j] * dq_[i]);
      if (den > 0) u = std::min(u, (aeff_[i] * std::abs(dq_[j]) + aeff_[j] * std::abs(dq_[i])) / den);
    }
  return u;
}

double PhaseLimits::max_u(int piece, double s) const {
  load(piece, s);
  return loaded_max_u();
}

double PhaseLimits::velocity_max_u(int piece, double s) const {
  load(piece, s);
  return loaded_velocity_max_u();
}

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
  load(piece, s);
  AccelRange r{-kInf, kInf};
  // Joint j: dq_j a + ddq_j (u_from + 2 a k) in [-a_j, a_j], a_j with half the rounding allowance
  // within_limits grants: near a joint turn (dq_j ~ 0) the bound's own rounding error is
  // amplified by 1 / dq_j, and the allowance absorbs it.
  for (Eigen::Index j = 0; j < dq_.size(); ++j) {
    const double c = dq_[j] + 2 * k * ddq_[j], offset = ddq_[j] * u_from, limit = aeff_[j] * (1 + 0.5 * kRounding);
    if (std::abs(c) <= kStill) {
      if (k != 0 && std::abs(offset) > limit) r.lo = kInf, r.hi = -kInf;  // no a fits
      continue;
    }
    double lo = (-limit - offset) / c, hi = (limit - offset) / c;
    if (c < 0) std::swap(lo, hi);
    r.lo = std::max(r.lo, lo), r.hi = std::min(r.hi, hi);
  }
  if (k > 0) r.lo = std::max(r.lo, -u_from / (2 * k));  // the speed reached stays real
  if (k < 0) r.hi = std::min(r.hi, u_from / (-2 * k));
  return r;
}

bool PhaseLimits::within_limits(int piece, double s, double u, double a, bool shrunk) const {
  load(piece, s);
  const Eigen::VectorXd& vmax = shrunk ? veff_ : vmax_;
  const Eigen::VectorXd& amax = shrunk ? aeff_ : amax_;
  const double sd = std::sqrt(std::max(u, 0.0));
  for (Eigen::Index j = 0; j < dq_.size(); ++j) {
    if (std::abs(dq_[j]) * sd > vmax[j] * (1 + kRounding)) return false;
    if (std::abs(dq_[j] * a + ddq_[j] * u) > amax[j] * (1 + kRounding)) return false;
  }
  return true;
}

bool PhaseLimits::step_within_limits(int piece, double s0, double u0, double s1, double u1, double a) const {
  const double s[3] = {s0, 0.5 * (s0 + s1), s1}, u[3] = {u0, 0.5 * (u0 + u1), u1};
  acc_.resize(dq_.size(), 3), vel2_.resize(dq_.size(), 3);
  for (int k = 0; k < 3; ++k) {
    load(piece, s[k]);
    acc_.col(k) = dq_ * a + ddq_ * u[k];
    vel2_.col(k) = dq_.cwiseAbs2() * std::max(u[k], 0.0);
  }
  for (Eigen::Index j = 0; j < dq_.size(); ++j)
    if (!parabola_within(acc_(j, 0), acc_(j, 1), acc_(j, 2), amax_[j] * (1 + kRounding)) ||
        !parabola_within(vel2_(j, 0), vel2_(j, 1), vel2_(j, 2), vmax_[j] * vmax_[j] * (1 + 2 * kRounding)))
      return false;
  return true;
}

}  // namespace dmgplace::runtime::detail
