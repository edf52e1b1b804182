#pragma once
// One collision space per grasp (the object held differently, the fingers at that grasp's
// opening), made on first use and shared by the goal validator, the motion planner's workers and
// the local optimiser. Thread-safe.
#include <map>
#include <memory>
#include <mutex>

#include "dmgplace/runtime/grasp/reachable_grasps.hpp"
#include "dmgplace/runtime/placement/placement_world.hpp"

namespace dmgplace::runtime {

class PerGraspCheckers {
 public:
  PerGraspCheckers(const PlacementWorld& world, std::vector<ReachableGrasp> grasps, Eigen::VectorXd q0);
  int size() const { return int(grasps_.size()); }
  const ReachableGrasp& grasp(int g) const { return grasps_[std::size_t(g)]; }
  const std::vector<ReachableGrasp>& grasps() const { return grasps_; }
  std::shared_ptr<const TwoLayerChecker> checker(int g);
  // The start configuration is collision-free with the object held this way, and the grasp was
  // not excluded.
  bool usable(int g);
  // Leaves grasp g out from now on (usable(g) is false): the pusher cannot perform its in-hand actions.
  void exclude(int g);
  const CheckCounters& counters() const { return *counters_; }

 private:
  const PlacementWorld* world_;
  std::vector<ReachableGrasp> grasps_;
  Eigen::VectorXd q0_;
  std::shared_ptr<CheckCounters> counters_ = std::make_shared<CheckCounters>();
  std::mutex mutex_;
  std::map<int, std::shared_ptr<const TwoLayerChecker>> checkers_;
  std::map<int, bool> usable_;
};

}  // namespace dmgplace::runtime
