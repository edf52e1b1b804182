#pragma once
// Is a sampled placement a goal? Algorithm 2, lines 5-8, for every sample: stable on its region,
// object free of the environment, objective better than the best so far, a grasp (Algorithm 3),
// an IK solution for it, and an arm free of collisions holding the object that way. Every
// constraint is evaluated even when an earlier one fails, so invalid samples still earn the
// relaxed MCTS reward of the parts they satisfy (reachable regions steer the tree even where the
// object collides) and kinematically reachable grasps reach the grasp cache.
#include <random>

#include "dmgplace/runtime/placement/grasp_selector.hpp"
#include "dmgplace/runtime/placement/objective.hpp"
#include "dmgplace/runtime/placement/placement_world.hpp"
#include "dmgplace/runtime/robot/ik.hpp"

namespace dmgplace::runtime {

struct GoalCheck {
  bool stable = false, object_free = false, improves = false, reachable = false, arm_free = false;
  int grasp = -1;
  bool cached_grasp = false;  // the grasp came from Algorithm 3's cache
  double objective = 0;
  Eigen::VectorXd q;  // the IK solution, object lifted above its resting pose (when reachable)
  bool valid() const { return stable && object_free && improves && reachable && arm_free; }
  // Kinematically reachable in the paper's sense: an IK solution that is collision-free with
  // the object held by this grasp (which includes the object against the scene).
  bool kinematically_reachable() const { return reachable && arm_free; }
  // 1 when valid. Until a first solution exists, otherwise the weighted share of satisfied
  // constraints (the authors' weights), the objective's share only for a stable, object-free pose;
  // once one exists (`solved`), 0: the relaxation only leads the tree to a first goal.
  double reward(const PlacementOptions& o, bool solved) const;
};

struct GoalCounters {
  long samples = 0, stable = 0, object_free = 0, improving = 0, cached_grasps = 0, ik_calls = 0, ik_solutions = 0,
       reachable = 0, object_checks = 0, arm_checks = 0, goals = 0;
};

class GoalValidator {
 public:
  GoalValidator(const PlacementWorld& world, const SearchSpace& space, const Objective& objective,
                PerGraspCheckers& per_grasp, GraspSelector& selector, const PlacementQuery& query);
  // `better(value)`: whether an objective value would improve on the best solution so far.
  GoalCheck check(const PlacementSample& s, const std::function<bool(double)>& better, std::mt19937_64& rng);
  Eigen::Isometry3d lifted(const Eigen::Isometry3d& resting) const;
  const GoalCounters& counters() const { return counters_; }

 private:
  const PlacementWorld* world_;
  const SearchSpace* space_;
  const Objective* objective_;
  PerGraspCheckers* per_grasp_;
  GraspSelector* selector_;
  const PlacementQuery* query_;
  IkSolver ik_;
  GoalCounters counters_;
};

}  // namespace dmgplace::runtime
