#include "dmgplace/runtime/placement/grasp_selector.hpp"

namespace dmgplace::runtime {

GraspSelector::GraspSelector(GraspSpaces& spaces, PlacementVariant variant, double p_accept, int tries, HandFree hand_free)
    : spaces_(&spaces), variant_(variant), p_accept_(p_accept), tries_(std::max(1, tries)), hand_free_(std::move(hand_free)) {}

bool GraspSelector::acceptable(int g, const Eigen::Isometry3d& pose) {
  tried_[std::size_t(g)] = 1;
  ++hand_checks_;
  return hand_free_(g, pose) && spaces_->usable(g);
}

int GraspSelector::select(const PlacementTree& tree, int node, const Eigen::Isometry3d& pose, std::mt19937_64& rng) {
  const int n = spaces_->size();
  if (n == 0) return -1;
  tried_.assign(std::size_t(n), 0);
  std::uniform_real_distribution<double> u(0, 1);
  if (variant_ == PlacementVariant::NoRegrasp) return acceptable(0, pose) ? 0 : -1;
  if (variant_ == PlacementVariant::Full) {
    bool cached = false;
    for (int a = node; a >= 0; a = tree.node(a).parent)
      for (int g : tree.node(a).grasps) {
        cached = true;
        if (tried_[std::size_t(g)]) continue;
        if (acceptable(g, pose) && u(rng) < p_accept_) return g;
      }
    if (!cached && acceptable(0, pose)) return 0;
  }
  // Uniformly among untried grasps (the random-grasp variant: among all).
  std::vector<int> pool;
  for (int g = 0; g < n; ++g)
    if (variant_ == PlacementVariant::RandomGrasp || !tried_[std::size_t(g)]) pool.push_back(g);
  for (int t = 0; t < tries_ && !pool.empty(); ++t) {
    std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
    const std::size_t k = pick(rng);
    const int g = pool[k];
    pool.erase(pool.begin() + std::ptrdiff_t(k));
    if (acceptable(g, pose)) return g;
  }
  return -1;
}

}  // namespace dmgplace::runtime
