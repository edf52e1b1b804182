#pragma once
// The anytime placement planner (the paper's Algorithm 1): MCTS goal sampling over the placement
// hierarchy, grasp selection with caches, goals handed to the multi-grasp motion planner, local
// optimisation of every reached placement, and a published best that only ever improves.
//
//   PlacementWorld world(robot, object, env);
//   PlacementPlanner planner(world, query);
//   auto result = planner.run(stop_after_seconds(5.0), [](const PlacementSolution& s) { ... });
// Embedding applications use dmgplace/runtime.hpp, which wraps this without exposing the world.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dmgplace/runtime/placement/placement_query.hpp"
#include "dmgplace/runtime/placement/placement_result.hpp"
#include "dmgplace/runtime/placement/placement_world.hpp"
#include "dmgplace/runtime/stop_condition.hpp"

namespace dmgplace::runtime {

class PlacementPlanner {
 public:
  using Callback = std::function<void(const PlacementSolution&)>;
  // Checks the query against the world (dmgplace::Error naming the field when it does not fit).
  PlacementPlanner(const PlacementWorld& world, PlacementQuery query);
  ~PlacementPlanner();
  // Runs until `stop()` returns true (checked between rounds), calling `on_solution` for every
  // improvement as it is found. Synchronous mode (options.threads == 0) is deterministic.
  PlacementResult run(const StopCondition& stop, const Callback& on_solution = {});

 private:
  struct Run;
  const PlacementWorld* world_;
  PlacementQuery query_;
  std::unique_ptr<class PushPlanner> pusher_;  // when the query names a pusher arm
};

}  // namespace dmgplace::runtime
