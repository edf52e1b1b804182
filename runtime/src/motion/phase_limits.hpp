#pragma once
// Per-joint velocity and acceleration limits as seen along a BlendedPath, in the phase plane
// (s, u) with u = s_dot^2 (Kunz & Stilman 2012): joint velocities are f'(s) s_dot and joint
// accelerations f'(s) s_ddot + f''(s) u. Working in u keeps a step of constant s_ddot linear
// in s.
//
// The phase plane is built on limits shrunk by `margin` (a relative amount): steps of constant
// s_ddot between knots only match the true bounds at their ends, and the margin is the room the
// step's interior may drift into. within_limits() checks the true limits.
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "blended_path.hpp"

namespace dmgplace::runtime::detail {

// The path accelerations s_ddot every joint allows at one state; empty when lo > hi (above the
// acceleration limit curve).
struct AccelRange {
  double lo, hi;
};

class PhaseLimits {
 public:
  PhaseLimits(const BlendedPath& path, const Eigen::VectorXd& max_velocity, const Eigen::VectorXd& max_acceleration,
              double margin);
  PhaseLimits(const PhaseLimits&) = delete;  // the cache points into its own storage
  PhaseLimits& operator=(const PhaseLimits&) = delete;

  const BlendedPath& path() const { return path_; }

  // The limit curve at s on `piece`: the largest u both the velocity limits and the acceleration
  // limits (some s_ddot fits every joint) allow. Infinite only where nothing binds, never on a path.
  double max_u(int piece, double s) const;
  // The velocity limits' part of it: the velocity limit curve.
  double velocity_max_u(int piece, double s) const;
  // Its slope d(max_u)/ds from the left (side < 0), the right (side > 0) or both (side == 0),
  // measured within `piece`; of the velocity limit curve alone if `velocity_only`.
  double max_u_slope(int piece, double s, int side, bool velocity_only = false) const;
  // The s_ddot range on the limit curve just left (side < 0) or right (side > 0) of s, or at s
  // (side == 0). At a joint turn the turning joint's bound is ill-conditioned at s itself (its
  // velocity factor is ~0), and each side has its own value.
  AccelRange side_accel_range(int piece, double s, int side) const;
  AccelRange accel_range(int piece, double s, double u) const { return reach_range(piece, s, u, 0); }
  // The s_ddot `a` that keep every joint within its acceleration limit at s when the speed there
  // is reached by holding `a` from elsewhere: u = u_from + 2 a k (k = +h at the far end of a step
  // forward over h, -h at the far end of a step back). Each joint's acceleration is linear in a.
  AccelRange reach_range(int piece, double s, double u_from, double k) const;
  // Its upper or lower end alone (the integration needs one side only), at half the divisions.
  double reach_bound(int piece, double s, double u_from, double k, bool upper) const;
  double reach_max(int piece, double s, double u_from, double k) const {
    return reach_bound(piece, s, u_from, k, true);
  }
  double reach_min(int piece, double s, double u_from, double k) const {
    return reach_bound(piece, s, u_from, k, false);
  }
  double accel_max(int piece, double s, double u) const { return reach_max(piece, s, u, 0); }
  double accel_min(int piece, double s, double u) const { return reach_min(piece, s, u, 0); }
  // Moving at (s, u) on `piece` with s_ddot = a keeps every joint within its limits (the true
  // ones, or the shrunk ones the phase plane is built on), up to a relative 1e-9 for rounding.
  bool within_limits(int piece, double s, double u, double a, bool shrunk = false) const;
  // The same for the whole step (s0, u0) - (s1, u1) at s_ddot a on `piece`, against the true
  // limits: each joint's acceleration and squared velocity along the step are fitted by the
  // parabola through their values at its ends and middle, and the parabola's extremum checked.
  bool step_within_limits(int piece, double s0, double u0, double s1, double u1, double a) const;

 private:
  // One evaluated state of the path: f', f'' there and, once asked for, its limit curves. The
  // integration revisits a handful of points (a step's ends and middle) many times over.
  struct Point {
    int piece = -1;
    double s = 0;
    bool curved = false;  // f'' != 0 (an arc)
    bool has_max_u = false, has_velocity_max_u = false;
    double max_u = 0, velocity_max_u = 0;
    double* dq = nullptr;  // into cache_store_
    double* ddq = nullptr;
  };
  static constexpr int kCached = 4;

  std::pair<double, double> slope_interval(int piece, double s, int side) const;
  // Valid until the next kCached loads of other points.
  Point& load(int piece, double s) const;
  double velocity_max_u(Point& p) const;
  double max_u(Point& p) const;

  const BlendedPath& path_;
  const Eigen::Index n_;
  Eigen::VectorXd vmax_, amax_;  // true limits
  Eigen::VectorXd veff_, aeff_;  // shrunk by the margin
  mutable Point cache_[kCached];
  mutable std::vector<double> cache_store_;  // f', f'' of each cached point
  mutable int cache_next_ = 0;               // the slot the next miss replaces
  mutable std::vector<double> acc_, vel2_;   // step_within_limits' scratch: 3 values per joint
};

}  // namespace dmgplace::runtime::detail
