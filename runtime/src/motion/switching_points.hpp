#pragma once
// Switching points of the phase plane (Kunz & Stilman 2012): the points of the limit curve the
// time-optimal profile may touch, where the hardest braking curve arriving from the left and
// the profile leaving to the right both stay under the limit curve. When forward
// integration runs into the limit curve, the profile is repaired by braking backwards from the
// next switching point. Private to the runtime.
#include <optional>

#include "phase_limits.hpp"

namespace dmgplace::runtime::detail {

struct SwitchingPoint {
  double s, u;  // u = s_dot^2, on the limit curve
};

// The first switching point at or after `from` and strictly after `after` (the previous one, so
// integration always moves on), or none before the path's end.
std::optional<SwitchingPoint> next_switching_point(const PhaseLimits& limits, double from, double after);

}  // namespace dmgplace::runtime::detail
