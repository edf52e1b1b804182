#include "dmgplace/runtime/grasp/grasp_graph.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>

namespace dmgplace::runtime {

GraspGraph::GraspGraph(const formats::Dmg& dmg, double rotation_weight) : dmg_(dmg) {
  const int k = dmg_.angle_count();
  step_ = dmg_.angle_step_deg * std::numbers::pi / 180;
  for (std::size_t i = 0; i < dmg_.nodes.size(); ++i) {
    first_state_.push_back(int(states_.size()));
    const auto& n = dmg_.nodes[i];
    for (int j = 0; j < n.angle_count; ++j) states_.push_back({int(i), (n.first_angle + j) % k});
  }
  first_state_.push_back(int(states_.size()));
  std::vector<std::tuple<int, int, double>> edges;
  std::vector<GraspMove> kinds;
  auto add = [&](int a, int b, double c, GraspMove m) {
    edges.emplace_back(a, b, c);
    kinds.push_back(m);
  };
  // Edges are added per source state in a fixed order (rotations, then translations) so that the
  // compressed graph's edge order equals `kinds` after a stable bucket by source.
  std::vector<std::vector<std::pair<int, double>>> translations(states_.size());
  for (auto [a, b] : dmg_.edges) {
    const double d = (dmg_.nodes[a].position - dmg_.nodes[b].position).norm();
    for (int s = first_state_[a]; s < first_state_[a + 1]; ++s) {
      const int t = find(b, states_[s].angle);
      if (t >= 0) translations[s].push_back({t, d});
    }
  }
  for (int s = 0; s < size(); ++s) {
    const auto& n = dmg_.nodes[states_[s].node];
    const int j = s - first_state_[states_[s].node];
    const bool full = n.angle_count == k;
    if (n.angle_count > 1) {
      if (j + 1 < n.angle_count || full) add(s, first_state_[states_[s].node] + (j + 1) % n.angle_count, step_ * rotation_weight, GraspMove::Rotation);
      if (j > 0 || full) add(s, first_state_[states_[s].node] + (j + n.angle_count - 1) % n.angle_count, step_ * rotation_weight, GraspMove::Rotation);
    }
    for (auto [t, d] : translations[s]) add(s, t, d, GraspMove::Translation);
  }
  graph_ = WeightedGraph::from_edges(size(), edges);
  moves_ = std::move(kinds);  // edges were added grouped by ascending source: same order
}

int GraspGraph::find(int node, int angle) const {
  const auto& n = dmg_.nodes[node];
  const int k = dmg_.angle_count();
  const int j = ((angle - n.first_angle) % k + k) % k;
  return j < n.angle_count ? first_state_[node] + j : -1;
}

Eigen::Isometry3d GraspGraph::tcp_pose(int s) const {
  const auto& n = dmg_.nodes[states_[s].node];
  const double a = states_[s].angle * step_;
  Eigen::Matrix3d r;
  r.col(1) = n.normal;
  r.col(2) = std::cos(a) * n.zero_axis + std::sin(a) * n.normal.cross(n.zero_axis);
  r.col(0) = r.col(1).cross(r.col(2));
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  t.translation() = 0.5 * (n.position + n.opposite_point);
  return t;
}

double GraspGraph::opening(int s) const {
  const auto& n = dmg_.nodes[states_[s].node];
  return (n.position - n.opposite_point).norm();
}

int GraspGraph::snap(const Eigen::Isometry3d& tcp, double opening, double* distance) const {
  const Eigen::Matrix3d flip = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Quaterniond q0(tcp.linear()), q1(Eigen::Matrix3d(tcp.linear() * flip));
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int s = 0; s < size(); ++s) {
    const Eigen::Isometry3d p = tcp_pose(s);
    const Eigen::Quaterniond q(p.linear());
    const double rot = std::min(q.angularDistance(q0), q.angularDistance(q1));
    double d = (p.translation() - tcp.translation()).norm() + snap_weight * rot;
    if (opening >= 0) d += std::abs(this->opening(s) - opening);
    if (d < best_d) best_d = d, best = s;
  }
  if (distance) *distance = best_d;
  return best;
}

}  // namespace dmgplace::runtime
