#pragma once
// When an anytime query stops: a callable polled between rounds, true meaning "stop now". One type
// and one pair of factories for the embedding API (dmgplace::place) and the planner inside it.
#include <functional>

#include "dmgplace/runtime/export.hpp"

namespace dmgplace::runtime {

using StopCondition = std::function<bool()>;

// True once `seconds` have passed since the call (NaN or <= 0: at once; at most a year).
DMGPLACE_RUNTIME_EXPORT StopCondition stop_after_seconds(double seconds);
// True from the `iterations`-th poll on: a deterministic budget.
DMGPLACE_RUNTIME_EXPORT StopCondition stop_after_iterations(long iterations);

}  // namespace dmgplace::runtime
