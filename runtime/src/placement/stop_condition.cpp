#include "dmgplace/runtime/stop_condition.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

namespace dmgplace::runtime {

StopCondition stop_after_seconds(double seconds) {
  using Clock = std::chrono::steady_clock;
  // Clamped before the cast: 1e12 s in nanoseconds overflows, wrapping the deadline into the past.
  constexpr double kYear = 365.0 * 24 * 3600;
  const double s = std::isnan(seconds) ? 0.0 : std::clamp(seconds, 0.0, kYear);
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  return [end] { return Clock::now() >= end; };
}

StopCondition stop_after_iterations(long iterations) {
  auto left = std::make_shared<long>(iterations);
  return [left] { return (*left)-- <= 0; };
}

}  // namespace dmgplace::runtime
