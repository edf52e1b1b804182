#include "dmgplace/runtime/placement/grasp_selector.hpp"

#include <algorithm>

namespace dmgplace::runtime {

GraspSelector::GraspSelector(PerGraspCheckers& per_grasp, const PlacementTree& tree, PlacementVariant variant,
                             double p_accept, int hand_tries, HandFree hand_free)
    : per_grasp_(&per_grasp), tree_(&tree), variant_(variant), p_accept_(p_accept),
      hand_tries_(std::max(0, hand_tries)), hand_free_(std::move(hand_free)), in_g_(std::size_t(per_grasp.size()), 0),
      unusable_(std::size_t(per_grasp.size()), 0) {}

void GraspSelector::cache(int node, int grasp) {
  for (int n = node; n >= 0; n = tree_->node(n).parent) {
    if (node_grasps_.size() <= std::size_t(n)) node_grasps_.resize(std::size_t(n) + 1);
    auto& g = node_grasps_[std::size_t(n)];
    if (std::find(g.begin(), g.end(), grasp) == g.end()) g.push_back(grasp);
  }
}

void GraspSelector::record(int node, int grasp, bool reached) {
  if (variant_ != PlacementVariant::Full || grasp < 0) return;
  for (int n = node; n >= 0 && tree_->node(n).parent >= 0; n = tree_->node(n).parent) {
    Tries& t = tries_[key(n, grasp)];
    t.reached += reached;
    ++t.tried;
  }
}

double GraspSelector::acceptance(int node, int grasp) const {
  for (int n = node; n >= 0 && tree_->node(n).parent >= 0; n = tree_->node(n).parent) {
    const auto it = tries_.find(key(n, grasp));
    if (it != tries_.end()) return it->second.reached > 0 ? 1.0 : 1.0 / double(it->second.tried + 1);
  }
  return 1.0;
}

std::vector<int> GraspSelector::cached(int node) const {
  std::vector<int> out;
  // Up to, not including, the root (Algorithm 3, line 3).
  for (int n = node; n >= 0 && tree_->node(n).parent >= 0; n = tree_->node(n).parent) {
    if (std::size_t(n) >= node_grasps_.size()) continue;
    for (int g : node_grasps_[std::size_t(n)])
      if (std::find(out.begin(), out.end(), g) == out.end()) out.push_back(g);
  }
  return out;
}

int GraspSelector::draw(bool skip_cached, std::mt19937_64& rng) {
  const int n = per_grasp_->size();
  std::uniform_int_distribution<int> pick(0, n - 1);
  // Rejection from the set minus G and the known-unusable grasps: cheap while those are few,
  // which is the common case with thousands of grasps. After 4n misses, list what is left.
  for (int t = 0; t < 4 * n; ++t) {
    const int g = pick(rng);
    if ((skip_cached && in_g_[std::size_t(g)] == stamp_) || unusable_[std::size_t(g)]) continue;
    if (per_grasp_->usable(g)) return g;
    unusable_[std::size_t(g)] = 1;
  }
  std::vector<int> left;
  for (int g = 0; g < n; ++g)
    if (!(skip_cached && in_g_[std::size_t(g)] == stamp_) && !unusable_[std::size_t(g)]) left.push_back(g);
  while (!left.empty()) {
    std::uniform_int_distribution<std::size_t> k(0, left.size() - 1);
    const std::size_t i = k(rng);
    if (per_grasp_->usable(left[i])) return left[i];
    unusable_[std::size_t(left[i])] = 1;
    left.erase(left.begin() + std::ptrdiff_t(i));
  }
  return -1;
}

GraspChoice GraspSelector::select(int node, const Eigen::Isometry3d& pose, std::mt19937_64& rng) {
  const int n = per_grasp_->size();
  if (n == 0) return {};
  if (variant_ == PlacementVariant::NoRegrasp) return {per_grasp_->usable(0) ? 0 : -1, false};
  ++stamp_;  // a new stamp per call marks "in G" without clearing the array
  if (variant_ == PlacementVariant::RandomGrasp) return {draw(false, rng), false};
  // Lines 1-7: G in the order cached, nearest node first (stamps dedupe in O(1)).
  g_.clear();
  for (int a = node; a >= 0 && tree_->node(a).parent >= 0; a = tree_->node(a).parent)
    if (std::size_t(a) < node_grasps_.size())
      for (int k : node_grasps_[std::size_t(a)])
        if (in_g_[std::size_t(k)] != stamp_) in_g_[std::size_t(k)] = stamp_, g_.push_back(k);
  if (g_.empty()) g_.push_back(0), in_g_[0] = stamp_;  // line 7: g0 first when nothing is cached
  std::uniform_real_distribution<double> u(0, 1);
  for (int k : g_) {
    if (unusable_[std::size_t(k)]) continue;
    ++hand_checks_;
    if (!hand_free_(k, pose)) continue;
    if (!per_grasp_->usable(k)) {
      unusable_[std::size_t(k)] = 1;
      continue;
    }
    if (u(rng) <= p_accept_ * acceptance(node, k)) return {k, true};
  }
  // Lines 14-16: from G(g0) \ G, or from all of G(g0) when G covers it; the first draws
  // hand-checked (beyond the paper, see the header).
  for (int t = 0; t < hand_tries_; ++t) {
    const int k = draw(true, rng);
    if (k < 0) break;
    ++hand_checks_;
    if (hand_free_(k, pose)) return {k, false};
  }
  // Every hand tried collides here: no grasp, so no IK (a colliding hand cannot give a free arm,
  // and an IK success alone would credit this node with "reachable" it is not).
  if (hand_tries_ > 0) return {};
  const int from_rest = draw(true, rng);
  return {from_rest >= 0 ? from_rest : draw(false, rng), false};
}

}  // namespace dmgplace::runtime
