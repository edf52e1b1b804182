#pragma once
// How far a ball rigidly attached to a link can move while the joints move at constant rates
// (q(t) = q + t u): the speed bounds behind the fast layer's free-distance certificates.
//
// Every point x moves at |x'| <= sum_j |u_j| r_j(t), r_j its distance to joint j's axis. Three
// bounds on the displacement D(t), each valid alone:
// - static: r_j(t) <= reach_j (the farthest the ball gets from the axis, whatever the other
//   joints), so D <= t sum |u_j| reach_j (`reach_speed`);
// - Gronwall: r_j(t) <= r_j(0) + D(t), so with V0 = sum |u_j| r_j(0) (`local_speed`) and
//   W = sum |u_j| over revolute joints (`turn_rate`), D <= G(t) = V0 / W (exp(W t) - 1);
// - Taylor: x's velocity at 0 is the vector J u, at most a = |v(c)| + |omega| R (`first_order`),
//   and it drifts by at most sum_j |u_j| (W_j t r_j(0) + G(t)), W_j the turn rate of joint j's
//   frame (the joints above it, and it): D <= a t + S t^2 / 2 + V0 / W (exp(W t) - 1 - W t) with
//   S = sum |u_j| W_j r_j(0) (`second_order`). Joint motions that cancel make a << V0, so near
//   obstacles, where certificates are short, this one lasts longest.
// Distances are measured in a frame the listed joints do not move (the base, or for a link pair
// the last joint both links share); a pair's bound is the sum of its two balls' (`add`).
//
// Directional: a gap g to a convex obstacle proven along a separating direction n (convex_gap:
// the ball's solid lies at least g beyond the obstacle along n) closes only as fast as the solid's
// farthest point along -n advances, n . (x(t) - x(0)) for the x that maximises it; so the Taylor
// bound holds with a replaced by the first-order speed along n, |n . v(c)| + R |n x omega|
// (BallVelocity::along), the drift terms unchanged (they bound the whole velocity's change). A
// motion sliding along the obstacle then keeps a gap of a few millimetres for several steps.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dmgplace::runtime {

struct DisplacementBound {
  double reach_speed = 0, local_speed = 0, turn_rate = 0, first_order = 0, second_order = 0;

  // A bound for D_a + D_b (two balls moving independently).
  void add(const DisplacementBound& other);
  // The longest t with D(t) < clearance guaranteed (infinite when nothing moves). Given `enough`,
  // any guaranteed t >= enough may be returned instead: the cheap bounds first, the Taylor root
  // (and the logarithm) only when they fall short. 0 for a clearance that is not positive.
  double time_to_move(double clearance, double enough = std::numeric_limits<double>::infinity()) const;
  // The smallest of the three bounds on D(t) (for tests and plots).
  double displacement(double t) const;
  // The same bound for displacements along one direction: first order `along` (BallVelocity::along)
  // where that is less.
  DisplacementBound along(double first_order_along) const {
    DisplacementBound b = *this;
    b.first_order = std::min(first_order, first_order_along);
    return b;
  }
  // A clearance that should last t: displacement(t), 1% over (time_to_move's bound is a little
  // looser). A caller that stops refining a clearance there checks time_to_move and refines on
  // should it still fall short. Infinite for an infinite t.
  double clearance_for(double t) const {
    return std::isfinite(t) ? 1.01 * displacement(t) + 1e-9 : std::numeric_limits<double>::infinity();
  }

 private:
  double taylor_time(double clearance) const;
};

// log1p(x) / x from below for x >= 0, by log1p's [2/2] Pade form (one division, no libm call):
// (6 + 3x) / (6 + 6x + x^2), lowered by 1e-12 of itself for rounding (the form meets log1p to
// 1e-16 as x -> 0). Within 5e-7 of it up to x = 0.1, 0.12% at x = 1 (a unit test checks it stays below).
inline double log1p_ratio_lower(double x) { return (6.0 + 3.0 * x) / (6.0 + x * (6.0 + x)) * (1 - 1e-12); }

// A ball's first-order velocity field at q, per unit of joint motion: the center's velocity and
// the angular velocity, in the measuring frame.
struct BallVelocity {
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), linear = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
  double radius = 0;
  // The most any point of the ball around `at` of radius r, rigidly attached (the ball itself, or
  // one of a body's spheres), moves along the unit n per unit of time at first order (the motion's
  // either sense): |n . v(at)| + r |n x angular|.
  double along(const Eigen::Vector3d& n, const Eigen::Vector3d& at, double r) const {
    return std::abs(n.dot(linear + angular.cross(at - center))) + r * n.cross(angular).norm();
  }
  double along(const Eigen::Vector3d& n) const { return along(n, center, radius); }
};

// Builds a ball's bound from the joints that move it, given top of the chain first, each as seen
// at q in the measuring frame: its unit axis, a point on it, its rate u_j and the ball's reach.
class BallMotion {
 public:
  BallMotion(const Eigen::Vector3d& center, double radius) : center_(center), radius_(radius) {}
  void add_revolute(const Eigen::Vector3d& axis, const Eigen::Vector3d& origin, double rate, double reach);
  // The same with the center's lever arm known: axis x (center - origin), and its norm (callers
  // that bound one ball over several joint subsets compute each arm once).
  void add_revolute_arm(const Eigen::Vector3d& axis, const Eigen::Vector3d& arm, double arm_norm, double rate,
                        double reach);
  void add_prismatic(const Eigen::Vector3d& axis, double rate, double reach);
  DisplacementBound bound() const;
  BallVelocity velocity() const { return {center_, linear_, angular_, radius_}; }

 private:
  Eigen::Vector3d center_;
  double radius_;
  Eigen::Vector3d linear_ = Eigen::Vector3d::Zero(), angular_ = Eigen::Vector3d::Zero();
  double frame_turn_ = 0;  // turn rate of the last joint's frame: the joints above it, and it
  DisplacementBound b_;
};

}  // namespace dmgplace::runtime
