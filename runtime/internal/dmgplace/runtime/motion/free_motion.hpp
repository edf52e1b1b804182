#pragma once
// A collision-free joint-space motion between two configurations of any chain, under a validity
// test the caller gives: bidirectional RRT-Connect (ours, MultiGoalRRTConnect) with one goal, in
// a fixed budget. The retreat after release and the pusher's moves to and from its pushes use it.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"
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

// The start tree motions from one start leave for the next: each begins from it
// (MultiGoalRRTConnect::seed_start_tree: its edges re-checked under the new motion's validity where
// a path runs through them) and leaves its own, at most kMaxNodes (the first ones: a tree again).
// A tree from another start is not used.
struct MotionTree {
  static constexpr std::size_t kMaxNodes = 20000;
  std::vector<MultiGoalRRTConnect::SeedNode> nodes;
};

// A path from `from` to `to` (both ends included, every segment valid at budget.resolution), or
// empty when none was found within the budget (or an end is not valid). `tree` (optional): the
// start tree of earlier motions from `from`, updated.
JointPath plan_free_motion(const Kinematics& kin, const ValidityFn& valid, const Eigen::VectorXd& from,
                           const Eigen::VectorXd& to, const MotionBudget& budget, MotionTree* tree = nullptr);

}  // namespace dmgplace::runtime
