#pragma once
// The time-optimal speed profile along a BlendedPath, rest to rest (Kunz & Stilman 2012):
// integrate forward at the largest path acceleration, following the velocity limit curve where
// it can be followed; where the limit curve is hit, find the next switching point, integrate
// backward from it at the smallest path acceleration until that curve meets the forward one,
// splice, and go on from the switching point; finally brake backward from the end. Private to
// the runtime.
#include <vector>

#include "phase_limits.hpp"

namespace dmgplace::runtime::detail {

// The profile is piecewise: u = s_dot^2 is linear in s between knots (constant s_ddot `a` from a
// knot to the next), and no interval between knots crosses a piece boundary.
struct ProfileKnot {
  double s, u, a;
};

// Knots from (0, 0) to (length, 0), s strictly increasing. Throws std::runtime_error when the
// integration does not close (a step or iteration cap is reached, or a backward curve leaves the
// limits), which no valid input should cause.
std::vector<ProfileKnot> time_optimal_profile(const PhaseLimits& limits);

}  // namespace dmgplace::runtime::detail
