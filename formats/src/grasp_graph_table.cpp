#include "dmgplace/formats/grasp_graph_table.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "dmgplace/formats/object_artifact.hpp"

namespace dmgplace::formats {
namespace {

double step_rad(const Dmg& d) { return d.angle_step_deg * std::numbers::pi / 180; }

// TCP frame of finger 1 on n's contact turned by `angle` about the grasp axis.
Eigen::Isometry3d tcp_of(const DmgNode& n, double angle) {
  Eigen::Matrix3d r;
  r.col(1) = n.normal;
  r.col(2) = std::cos(angle) * n.zero_axis + std::sin(angle) * n.normal.cross(n.zero_axis);
  r.col(0) = r.col(1).cross(r.col(2));
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  t.translation() = 0.5 * (n.position + n.opposite_point);
  return t;
}

std::vector<int> first_states(const Dmg& d) {
  std::vector<int> first{0};
  for (const auto& n : d.nodes) first.push_back(first.back() + std::max(n.angle_count, 0));
  return first;
}

// State of (node, angle) given the node's first state, or -1 outside the node's interval.
int state_of(const Dmg& d, const std::vector<int>& first, int node, int angle) {
  const auto& n = d.nodes[node];
  const int k = d.angle_count();
  const int j = ((angle - n.first_angle) % k + k) % k;
  return j < n.angle_count ? first[node] + j : -1;
}

// The edges the DMG implies for the states already in t (offsets, targets, costs, moves): per
// state its rotations (next angle, previous angle), then translations in DMG edge order. No
// trigonometry, so the load-time check can recount them cheaply.
void add_implied_edges(const Dmg& dmg, const std::vector<int>& first, GraspGraphTable& t) {
  const int k = dmg.angle_count();
  const double rotation_cost = step_rad(dmg) * t.rotation_weight;
  std::vector<std::vector<std::pair<int, double>>> translations(t.state_node.size());
  for (auto [a, b] : dmg.edges) {
    const double d = (dmg.nodes[a].position - dmg.nodes[b].position).norm();
    for (int s = first[a]; s < first[a + 1]; ++s) {
      const int u = state_of(dmg, first, b, t.state_angle[s]);
      if (u >= 0) translations[s].push_back({u, d});
    }
  }
  t.offsets.assign(1, 0);
  for (int s = 0; s < t.size(); ++s) {
    const int node = t.state_node[s];
    const auto& n = dmg.nodes[node];
    const int j = s - first[node];
    const bool full = n.angle_count == k;
    auto add = [&](int u, double c, GraspMoveKind m) {
      t.targets.push_back(u);
      t.costs.push_back(c);
      t.moves.push_back(m);
    };
    if (n.angle_count > 1) {
      if (j + 1 < n.angle_count || full)
        add(first[node] + (j + 1) % n.angle_count, rotation_cost, GraspMoveKind::Rotation);
      // Two angles of a full circle: next and previous are the same state; store it once.
      if ((j > 0 || full) && !(full && n.angle_count == 2))
        add(first[node] + (j + n.angle_count - 1) % n.angle_count, rotation_cost, GraspMoveKind::Rotation);
    }
    for (auto [u, d] : translations[s]) add(u, d, GraspMoveKind::Translation);
    t.offsets.push_back(std::int32_t(t.targets.size()));
  }
}

}  // namespace

GraspGraphTable build_grasp_graph_table(const Dmg& dmg, double rotation_weight) {
  GraspGraphTable t;
  t.rotation_weight = rotation_weight;
  const int k = dmg.angle_count();
  const double step = step_rad(dmg);
  const auto first = first_states(dmg);
  for (std::size_t i = 0; i < dmg.nodes.size(); ++i) {
    const auto& n = dmg.nodes[i];
    for (int j = 0; j < n.angle_count; ++j) {
      const int angle = (n.first_angle + j) % k;
      t.state_node.push_back(std::int32_t(i));
      t.state_angle.push_back(angle);
      const Eigen::Isometry3d p = tcp_of(n, angle * step);
      const Eigen::Quaterniond q(p.linear());
      t.tcp.insert(t.tcp.end(),
                   {p.translation().x(), p.translation().y(), p.translation().z(), q.x(), q.y(), q.z(), q.w()});
      t.opening.push_back((n.position - n.opposite_point).norm());
    }
  }
  add_implied_edges(dmg, first, t);
  return t;
}

namespace {
// The states enumerate the nodes' angle intervals in order, each with its node's TCP and opening
// (the snap index); the first problem found, or none.
std::optional<std::string> state_problem(const Dmg& dmg, const GraspGraphTable& t, const std::vector<int>& first) {
  const int k = dmg.angle_count();
  for (std::size_t i = 0; i < dmg.nodes.size(); ++i)
    for (int j = 0; j < dmg.nodes[i].angle_count; ++j) {
      const int s = first[i] + j;
      if (t.state_node[s] != int(i) || t.state_angle[s] != (dmg.nodes[i].first_angle + j) % k)
        return "state " + std::to_string(s) + " is not angle " + std::to_string(j) + " of node " + std::to_string(i) +
               "'s interval";
    }
  const double step = step_rad(dmg);
  for (int s = 0; s < first.back(); ++s) {
    const auto& n = dmg.nodes[t.state_node[s]];
    const Eigen::Isometry3d e = tcp_of(n, t.state_angle[s] * step);
    const double* c = &t.tcp[7 * std::size_t(s)];
    const Eigen::Quaterniond q(c[6], c[3], c[4], c[5]);
    const bool pose_ok = (Eigen::Vector3d(c[0], c[1], c[2]) - e.translation()).norm() <= 1e-9 &&
                         std::abs(q.norm() - 1) <= 1e-9 && q.angularDistance(Eigen::Quaterniond(e.linear())) <= 1e-6;
    if (!pose_ok || !(std::abs(t.opening[s] - (n.position - n.opposite_point).norm()) <= 1e-9))
      return "snap index: state " + std::to_string(s) + "'s TCP pose or opening is not its node's";
  }
  return std::nullopt;
}

// Edge e (from state s): a target in range, a rotation to a neighbouring angle of the same node or
// a translation along a DMG edge at the same angle, and its move's cost; empty when sound.
std::string edge_problem(const Dmg& dmg, const GraspGraphTable& t, int s, int e,
                         const std::set<std::pair<int, int>>& dmg_edges) {
  const int states = int(t.state_node.size()), k = dmg.angle_count();
  const int u = t.targets[e];
  const std::string edge = "edge " + std::to_string(s) + " -> " + std::to_string(u);
  if (u < 0 || u >= states || u == s) return edge + ": target out of range or a self loop";
  if (!(t.costs[e] > 0) || !std::isfinite(t.costs[e])) return edge + ": cost is not positive and finite";
  const int a = t.state_node[s], b = t.state_node[u];
  double expected = 0;
  if (t.moves[e] == GraspMoveKind::Rotation) {
    const int d = ((t.state_angle[u] - t.state_angle[s]) % k + k) % k;
    if (a != b || (d != 1 && d != k - 1))
      return edge + ": a rotation that does not turn to a neighbouring angle of the same node";
    expected = step_rad(dmg) * t.rotation_weight;
  } else if (t.moves[e] == GraspMoveKind::Translation) {
    if (t.state_angle[s] != t.state_angle[u] || !dmg_edges.contains({a, b}))
      return edge + ": a translation that does not keep the angle along a DMG edge";
    expected = (dmg.nodes[a].position - dmg.nodes[b].position).norm();
  } else {
    return edge + ": unknown move type " + std::to_string(int(t.moves[e]));
  }
  if (std::abs(t.costs[e] - expected) > 1e-9 * (1 + expected)) return edge + ": cost differs from its move's cost";
  return {};
}
}  // namespace

std::vector<std::string> check_grasp_graph_table(const Dmg& dmg, const GraspGraphTable& t) {
  std::vector<std::string> p;
  const std::string w = "grasp_graph: ";
  if (!(t.rotation_weight > 0) || !std::isfinite(t.rotation_weight))
    p.push_back(w + "rotation weight must be positive and finite");
  const auto first = first_states(dmg);
  const int states = first.back();
  if (t.size() != states || t.state_angle.size() != t.state_node.size() || t.tcp.size() != 7 * t.state_node.size() ||
      t.opening.size() != t.state_node.size()) {
    p.push_back(w + "has " + std::to_string(t.size()) +
                " states (or tables of other lengths), the DMG's angle intervals give " + std::to_string(states));
    return p;
  }
  if (!p.empty()) return p;
  if (const auto why = state_problem(dmg, t, first)) {
    p.push_back(w + *why);
    if (why->rfind("snap index", 0) != 0) return p;  // the edges' checks read the states
  }
  if (t.offsets.size() != std::size_t(states) + 1 || t.offsets.front() != 0 ||
      std::size_t(t.offsets.back()) != t.targets.size() || !std::is_sorted(t.offsets.begin(), t.offsets.end()) ||
      t.costs.size() != t.targets.size() || t.moves.size() != t.targets.size()) {
    p.push_back(w + "edge offsets are not a compressed adjacency of the states, or edge tables differ in length");
    return p;
  }
  std::set<std::pair<int, int>> dmg_edges;
  for (auto [a, b] : dmg.edges) dmg_edges.insert({a, b});
  std::map<std::pair<int, int>, std::pair<double, GraspMoveKind>> edges;
  std::size_t bad = 0;
  for (int s = 0; s < states; ++s)
    for (int e = t.offsets[s]; e < t.offsets[s + 1]; ++e) {
      if (const std::string why = edge_problem(dmg, t, s, e, dmg_edges); !why.empty()) {
        if (bad++ == 0) p.push_back(w + why);
        continue;
      }
      edges[{s, t.targets[e]}] = {t.costs[e], t.moves[e]};
    }
  if (bad > 1) p.push_back(w + std::to_string(bad) + " bad edges in all");
  for (const auto& [e, v] : edges) {
    const auto r = edges.find({e.second, e.first});
    if (r == edges.end() || r->second.second != v.second ||
        std::abs(r->second.first - v.first) > 1e-12 * (1 + v.first)) {
      p.push_back(w + "edge " + std::to_string(e.first) + " -> " + std::to_string(e.second) +
                  " has no reverse of equal cost");
      break;
    }
  }
  if (p.empty()) {
    GraspGraphTable expected;  // the states are t's (checked above); only the edges are recounted
    expected.rotation_weight = t.rotation_weight;
    expected.state_node = t.state_node;
    expected.state_angle = t.state_angle;
    add_implied_edges(dmg, first, expected);
    if (expected.edge_count() != edges.size())
      p.push_back(w + "has " + std::to_string(edges.size()) + " distinct edges, the DMG implies " +
                  std::to_string(expected.edge_count()));
  }
  return p;
}

}  // namespace dmgplace::formats
