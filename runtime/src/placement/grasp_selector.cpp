#include "dmgplace/runtime/placement/grasp_selector.hpp"

namespace dmgplace::runtime {

GraspSelector::GraspSelector(GraspSpaces& spaces, PlacementVariant variant, double p_accept, int tries, HandFree hand_free)
    : spaces_(&spaces), variant_(variant), p_accept_(p_accept), tries_(std::max(1, tries)), hand_free_(std::move(hand_free)) {}

bool GraspSelector::acceptable(int g, const Eigen::Isometry3d& pose) {
  tried_[std::size_t(g)] = stamp_;
  ++hand_checks_;
  return hand_free_(g, pose) && spaces_->usable(g);
}

int GraspSelector::select(const PlacementTree& tree, int node, const Eigen::Isometry3d& pose, std::mt19937_64& rng) {
  const int n = spaces_->size();
  if (n == 0) return -1;
  // A new stamp per call marks "tried in this call" without clearing the array.
  if (tried_.size() != std::size_t(n)) tried_.assign(std::size_t(n), 0);
  ++stamp_;
  auto tried = [&](int g) { return tried_[std::size_t(g)] == stamp_; };
  std::uniform_real_distribution<double> u(0, 1);
  if (variant_ == PlacementVariant::NoRegrasp) return acceptable(0, pose) ? 0 : -1;
  if (variant_ == PlacementVariant::Full) {
    bool cached = false;
    for (int a = node; a >= 0; a = tree.node(a).parent)
      for (int g : tree.node(a).grasps) {
        cached = true;
        if (tried(g)) continue;
        if (acceptable(g, pose) && u(rng) < p_accept_) return g;
      }
    if (!cached && acceptable(0, pose)) return 0;
  }
  // Uniformly among untried grasps (the random-grasp variant: among all), by rejection: cheap
  // when few are tried, which is the common case with thousands of grasps.
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int t = 0, draws = 0; t < tries_ && draws < 8 * tries_; ++draws) {
    const int g = pick(rng);
    if (variant_ == PlacementVariant::Full && tried(g)) continue;
    ++t;
    if (acceptable(g, pose)) return g;
  }
  return -1;
}

}  // namespace dmgplace::runtime
