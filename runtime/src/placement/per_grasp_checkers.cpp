#include "dmgplace/runtime/placement/per_grasp_checkers.hpp"

namespace dmgplace::runtime {

PerGraspCheckers::PerGraspCheckers(const PlacementWorld& world, std::vector<ReachableGrasp> grasps, Eigen::VectorXd q0)
    : world_(&world), grasps_(std::move(grasps)), q0_(std::move(q0)) {}

std::shared_ptr<const TwoLayerChecker> PerGraspCheckers::checker(int g) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = checkers_.find(g);
  if (it != checkers_.end()) return it->second;
  auto c = std::make_shared<const TwoLayerChecker>(
      world_->grasp_checker(grasps_[std::size_t(g)].pose, grasps_[std::size_t(g)].opening, counters_));
  checkers_[g] = c;
  return c;
}

bool PerGraspCheckers::usable(int g) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = usable_.find(g);
    if (it != usable_.end()) return it->second;
  }
  // Exact, object against the palm too: a wrong "usable" would hand the planner a start state it
  // cannot leave, and the per-grasp spaces no longer check object against hand.
  const bool ok = world_->grasp_exact(grasps_[std::size_t(g)].pose, grasps_[std::size_t(g)].opening).is_free(q0_);
  std::lock_guard<std::mutex> lock(mutex_);
  return usable_.emplace(g, ok).first->second;  // an exclusion made meanwhile stands
}

void PerGraspCheckers::exclude(int g) {
  std::lock_guard<std::mutex> lock(mutex_);
  usable_[g] = false;
}

}  // namespace dmgplace::runtime
