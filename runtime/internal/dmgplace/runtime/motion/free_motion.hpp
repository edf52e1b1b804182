#pragma once
// A collision-free joint-space motion between two configurations of any chain, under a validity
// test the caller gives: bidirectional RRT-Connect (ours, MultiGoalRRTConnect) with one goal, in
// a fixed budget. The retreat after release and the pusher's moves to and from its pushes use it.
#include <Eigen/Core>
#include <cstdint>

#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime {

struct MotionBudget {
  double resolution = 0.05;  // joint-space check step (rad)
  long iterations = 5000;    // planner iterations: the budget that keeps synchronous runs deterministic
  double seconds = 1.0;      // and a wall-clock cap
  std::uint64_t seed = 1;
};

// A path from `from` to `to` (both ends included, every segment valid at budget.resolution), or
// empty when none was found within the budget (or an end is not valid).
JointPath plan_free_motion(const Kinematics& kin, const ValidityFn& valid, const Eigen::VectorXd& from,
                           const Eigen::VectorXd& to, const MotionBudget& budget);

}  // namespace dmgplace::runtime
