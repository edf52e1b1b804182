#pragma once
// Is a sampled placement a goal? Checks in the order of cost: stable on its region, object free of
// the environment, objective better than the best so far, a grasp whose hand fits (Algorithm 3),
// an IK solution, and an arm free of collisions holding the object that way. The indicators give
// the relaxed MCTS reward of samples that fail.
#include <random>

#include "dmgplace/runtime/placement/grasp_selector.hpp"
#include "dmgplace/runtime/placement/objective.hpp"
#include "dmgplace/runtime/placement/placement_world.hpp"
#include "dmgplace/runtime/robot/ik.hpp"

namespace dmgplace::runtime {

struct GoalCheck {
  bool stable = false, object_free = false, improves = false, reachable = false, arm_free = false;
  int grasp = -1;
  double objective = 0;
  Eigen::VectorXd q;  // the goal configuration, object lifted above its resting pose
  bool valid() const { return stable && object_free && improves && reachable && arm_free; }
  double reward(const PlacementOptions& o) const;
};

struct GoalCounters {
  long samples = 0, stable = 0, object_free = 0, with_grasp = 0, ik_calls = 0, ik_solutions = 0, object_checks = 0, arm_checks = 0, goals = 0;
};

class GoalValidator {
 public:
  GoalValidator(const PlacementWorld& world, const SearchSpace& space, const Objective& objective, GraspSpaces& spaces,
                GraspSelector& selector, const PlacementQuery& query);
  // `better(value)`: whether an objective value would improve on the best solution so far.
  GoalCheck check(const PlacementTree& tree, const PlacementSample& s, const std::function<bool(double)>& better,
                  std::mt19937_64& rng);
  Eigen::Isometry3d lifted(const Eigen::Isometry3d& resting) const;
  const GoalCounters& counters() const { return counters_; }

 private:
  const PlacementWorld* world_;
  const SearchSpace* space_;
  const Objective* objective_;
  GraspSpaces* spaces_;
  GraspSelector* selector_;
  const PlacementQuery* query_;
  IkSolver ik_;
  GoalCounters counters_;
};

}  // namespace dmgplace::runtime
