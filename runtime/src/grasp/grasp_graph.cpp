#include "dmgplace/runtime/grasp/grasp_graph.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace dmgplace::runtime {

GraspGraph::GraspGraph(const formats::ObjectArtifact& object) : GraspGraph(object.dmg, object.grasp_graph) {}

GraspGraph::GraspGraph(formats::Dmg dmg, const formats::GraspGraphTable& t) : dmg_(std::move(dmg)) {
  step_ = dmg_.angle_step_deg * std::numbers::pi / 180;
  for (int s = 0; s < t.size(); ++s) {
    states_.push_back({t.state_node[s], t.state_angle[s]});
    const double* c = &t.tcp[7 * std::size_t(s)];
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::Quaterniond(c[6], c[3], c[4], c[5]).normalized().toRotationMatrix();
    p.translation() = Eigen::Vector3d(c[0], c[1], c[2]);
    tcp_.push_back(p);
  }
  opening_ = t.opening;
  first_state_.assign(dmg_.nodes.size() + 1, 0);
  for (std::size_t i = 0; i < dmg_.nodes.size(); ++i) first_state_[i + 1] = first_state_[i] + dmg_.nodes[i].angle_count;
  graph_.offsets.assign(t.offsets.begin(), t.offsets.end());
  graph_.targets.assign(t.targets.begin(), t.targets.end());
  graph_.costs = t.costs;
  for (auto m : t.moves)
    moves_.push_back(m == formats::GraspMoveKind::Rotation ? GraspMove::Rotation : GraspMove::Translation);
}

int GraspGraph::find(int node, int angle) const {
  const auto& n = dmg_.nodes[node];
  const int k = dmg_.angle_count();
  const int j = ((angle - n.first_angle) % k + k) % k;
  return j < n.angle_count ? first_state_[node] + j : -1;
}

Eigen::Isometry3d GraspGraph::tcp_pose(int s) const { return tcp_[s]; }

int GraspGraph::snap(const Eigen::Isometry3d& tcp, std::optional<double> opening, double* distance) const {
  const Eigen::Matrix3d flip = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Quaterniond q0(tcp.linear()), q1(Eigen::Matrix3d(tcp.linear() * flip));
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int s = 0; s < size(); ++s) {
    const Eigen::Quaterniond q(tcp_[s].linear());
    const double rot = std::min(q.angularDistance(q0), q.angularDistance(q1));
    double d = (tcp_[s].translation() - tcp.translation()).norm() + snap_weight * rot;
    if (opening) d += std::abs(opening_[s] - *opening);
    if (d < best_d) best_d = d, best = s;
  }
  if (distance) *distance = best_d;
  return best;
}

}  // namespace dmgplace::runtime
