#pragma once
// Grasp selection (the paper's Algorithm 3): walk up the hierarchy from the sampled node and try
// the grasps cached there, accepting a hand-collision-free one with probability p_accept;
// otherwise draw untried grasps uniformly (the initial grasp first when nothing is cached).
#include <cstdint>
#include <functional>
#include <random>

#include "dmgplace/runtime/placement/grasp_spaces.hpp"
#include "dmgplace/runtime/placement/placement_query.hpp"
#include "dmgplace/runtime/placement/placement_tree.hpp"

namespace dmgplace::runtime {

class GraspSelector {
 public:
  // hand_free(g, object_pose): grasp g's hand is free of the environment with the object there.
  using HandFree = std::function<bool(int grasp, const Eigen::Isometry3d& object_pose)>;
  GraspSelector(GraspSpaces& spaces, PlacementVariant variant, double p_accept, int tries, HandFree hand_free);
  // A grasp index into spaces.grasps() (0 is g0), or -1 when none passes.
  int select(const PlacementTree& tree, int node, const Eigen::Isometry3d& object_pose, std::mt19937_64& rng);
  long hand_checks() const { return hand_checks_; }

 private:
  bool acceptable(int g, const Eigen::Isometry3d& pose);
  GraspSpaces* spaces_;
  PlacementVariant variant_;
  double p_accept_;
  int tries_;
  HandFree hand_free_;
  long hand_checks_ = 0;
  std::vector<std::uint32_t> tried_;  // == stamp_: tried in the current call
  std::uint32_t stamp_ = 0;
};

}  // namespace dmgplace::runtime
