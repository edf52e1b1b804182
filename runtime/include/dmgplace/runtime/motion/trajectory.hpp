#pragma once
// Timed trajectories: a joint path time-parameterised time-optimally under per-joint velocity and
// acceleration limits, as controllers execute it. The method is Kunz & Stilman's (2012, "Time-
// Optimal Trajectory Generation for Path Following with Bounded Acceleration and Velocity", the
// one MoveIt uses by default): the path's corners are blended with circular arcs that stay within
// `max_deviation` of the corner, then the fastest velocity along the path under both limits is
// found by integrating forward and backward along the phase plane's limit curves.
// Plain values: no planning library type.
#include <string>
#include <vector>

#include "dmgplace/runtime/export.hpp"
#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime {

// Per-joint limits, in the arm chain's joint order (rad/s and rad/s^2; m/s and m/s^2 for
// prismatic joints). Every value must be finite and > 0.
struct JointLimits {
  std::vector<double> velocity;
  std::vector<double> acceleration;
};

struct TimingOptions {
  double velocity_scaling = 1.0;      // (0, 1]: fraction of the velocity limits used, as MoveIt's
  double acceleration_scaling = 1.0;  // (0, 1]: ... and of the acceleration limits
  double max_deviation = 0.01;        // > 0: how far a blended corner may leave the path (rad)
  double sample_period = 0.01;        // > 0: time between the trajectory's points (s)
};

// Samples of the timed trajectory, every `sample_period` from 0 and at the end. positions,
// velocities and accelerations have one row per time, each row one value per joint. The first
// and last points are the path's first and last waypoints, at rest.
struct Trajectory {
  std::vector<double> time;
  std::vector<std::vector<double>> positions, velocities, accelerations;
  double duration() const { return time.empty() ? 0.0 : time.back(); }
  bool empty() const { return time.empty(); }
};

// Times `path` (>= 1 waypoint, each of limits' size). Consecutive duplicate waypoints are
// skipped; a path of one waypoint, or whose waypoints all coincide, gives a single point at
// t = 0. The arm stops at a corner turning straight back, or too sharply for an arc of radius
// 1e-6 within max_deviation (it would crawl through it anyway). Every sample is within the
// scaled limits: the integration keeps a relative 1e-6 inside them, so a sample exceeds a
// limit by at most rounding (~1e-9 relative). Throws std::invalid_argument naming the problem
// (a limit that is not finite and > 0, a scaling outside (0, 1], max_deviation or sample_period
// not finite and > 0, waypoints of the wrong size or not finite, more than 10 million samples)
// and std::runtime_error if the integration fails (never seen on a valid input).
DMGPLACE_RUNTIME_EXPORT Trajectory time_parameterize(const JointPath& path, const JointLimits& limits,
                                                     const TimingOptions& options = {});

}  // namespace dmgplace::runtime
