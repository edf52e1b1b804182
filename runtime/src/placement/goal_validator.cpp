#include "dmgplace/runtime/placement/goal_validator.hpp"

namespace dmgplace::runtime {
namespace {
IkOptions ik_options(const PlacementOptions& o) {
  IkOptions ik;
  ik.max_restarts = o.ik_restarts;
  return ik;
}
}  // namespace

double GoalCheck::reward(const PlacementOptions& o, bool solved) const {
  if (valid()) return 1.0;
  // Once a solution exists, the relaxation below would keep paying the subtree already solved
  // (its poses stay feasible, and the grasp cache keeps them reachable) nearly as much as a goal,
  // and any partial credit (an improving pose whose IK succeeds but whose arm always collides)
  // can hold the tree for good: only goals count from then on, UCB1 on the rate of new goals.
  if (solved) return 0.0;
  const double total =
      o.reward_arm_free + o.reward_object_free + o.reward_contact + o.reward_objective + o.reward_reachable;
  if (!(total > 0)) return 0.0;
  // The objective is credited only where the pose is a placement (stable, object free): an
  // unstable pose "improving" on the best would otherwise earn more than a feasible one that does
  // not, and MCTS settles in subtrees where nothing is stable (almost no stable samples).
  const bool feasible_improvement = improves && stable && object_free;
  return (o.reward_arm_free * arm_free + o.reward_object_free * object_free + o.reward_contact * stable +
          o.reward_objective * feasible_improvement + o.reward_reachable * reachable) /
         total;
}

GoalValidator::GoalValidator(const PlacementWorld& world, const SearchSpace& space, const Objective& objective,
                             PerGraspCheckers& per_grasp, GraspSelector& selector, const PlacementQuery& query)
    : world_(&world), space_(&space), objective_(&objective), per_grasp_(&per_grasp), selector_(&selector),
      query_(&query), ik_(world.kinematics(), ik_options(query.options)) {}

Eigen::Isometry3d GoalValidator::lifted(const Eigen::Isometry3d& resting) const {
  Eigen::Isometry3d x = resting;
  x.translation().z() += query_->options.lift;
  return x;
}

GoalCheck GoalValidator::check(const PlacementSample& s, const std::function<bool(double)>& better,
                               std::mt19937_64& rng) {
  GoalCheck c;
  ++counters_.samples;
  if (s.face < 0 || s.region < 0) return c;
  c.stable = space_->stable(s.face, s.region, s.pose);
  const Eigen::Isometry3d up = lifted(s.pose);
  ++counters_.object_checks;
  c.object_free = world_->exact().mesh_free(world_->object_mesh(), up);
  c.objective = objective_->value(s.pose);
  c.improves = better(c.objective);
  counters_.stable += c.stable;
  counters_.object_free += c.stable && c.object_free;
  counters_.improving += c.stable && c.object_free && c.improves;
  const GraspChoice choice = selector_->select(s.node, up, rng);
  c.grasp = choice.grasp;
  c.cached_grasp = choice.cached;
  if (c.grasp < 0) return c;
  counters_.cached_grasps += choice.cached;
  ++counters_.ik_calls;
  const IkResult ik = ik_.solve(up * per_grasp_->grasp(c.grasp).pose, query_->q0, rng);
  c.reachable = ik.success;
  if (!c.reachable) return c;
  ++counters_.ik_solutions;
  ++counters_.arm_checks;
  c.arm_free = per_grasp_->checker(c.grasp)->is_free(ik.q);
  c.q = ik.q;
  counters_.reachable += c.kinematically_reachable();
  counters_.goals += c.valid();
  return c;
}

}  // namespace dmgplace::runtime
