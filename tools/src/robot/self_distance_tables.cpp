#include "dmgplace/tools/robot/self_distance_tables.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "../env/parallel_for.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::tools {
namespace {

// Joints from `link` up to the root, nearest first.
std::vector<int> joints_to_root(const RobotModel& m, const std::vector<int>& parent_joint, int link) {
  std::vector<int> out;
  for (int l = link; parent_joint[std::size_t(l)] >= 0 && out.size() <= m.joints.size(); l = m.joints[std::size_t(parent_joint[std::size_t(l)])].parent)
    out.push_back(parent_joint[std::size_t(l)]);
  return out;
}

// The joints on the tree path between links a and b; `on_a_side[i]` when path[i] moves a (it is
// an ancestor joint of a below the common ancestor).
void tree_path(const RobotModel& m, const std::vector<int>& parent_joint, int a, int b, std::vector<int>& path,
               std::vector<char>& on_a_side) {
  const auto up_a = joints_to_root(m, parent_joint, a), up_b = joints_to_root(m, parent_joint, b);
  path.clear();
  on_a_side.clear();
  for (int j : up_a)
    if (std::find(up_b.begin(), up_b.end(), j) == up_b.end()) path.push_back(j), on_a_side.push_back(1);
  for (int j : up_b)
    if (std::find(up_a.begin(), up_a.end(), j) == up_a.end()) path.push_back(j), on_a_side.push_back(0);
}

// Largest distance from joint k's origin of any point of `link`'s spheres: the joint origins from
// the link up to k are rigid offsets (every joint between is revolute or fixed), plus the farthest
// sphere surface in the link frame.
double slope_bound(const RobotModel& m, const std::vector<int>& parent_joint, int link, int k,
                   const std::vector<formats::LinkSphere>& link_spheres) {
  double reach = 0;
  for (const auto& s : link_spheres) reach = std::max(reach, s.center.norm() + s.radius);
  for (int l = link; parent_joint[std::size_t(l)] >= 0;) {
    const int j = parent_joint[std::size_t(l)];
    if (j == k) return reach;
    reach += m.joints[std::size_t(j)].origin.translation().norm();
    l = m.joints[std::size_t(j)].parent;
  }
  return std::numeric_limits<double>::infinity();  // not reached: k is not above the link
}

bool spheres_overlap(const std::vector<formats::LinkSphere>& a, const std::vector<formats::LinkSphere>& b,
                     const Eigen::Isometry3d& Ta, const Eigen::Isometry3d& Tb) {
  for (const auto& sa : a) {
    const Eigen::Vector3d ca = Ta * sa.center;
    for (const auto& sb : b)
      if ((ca - Tb * sb.center).norm() < sa.radius + sb.radius) return true;
  }
  return false;
}

float round_down(double d) {
  float f = float(d);
  if (double(f) > d) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return std::max(f, 0.0f);
}
}  // namespace

std::vector<formats::SelfDistanceTable> build_self_distance_tables(const runtime::Kinematics& kin,
                                                                   const std::vector<formats::LinkSphere>& spheres,
                                                                   const SelfTableOptions& o) {
  std::vector<formats::SelfDistanceTable> out;
  if (!o.enabled) return out;
  const RobotModel& m = kin.model();
  runtime::ExactChecker exact(kin, Scene{});
  const auto moving = kin.moving_links();
  std::vector<int> parent_joint(m.links.size(), -1);
  for (std::size_t j = 0; j < m.joints.size(); ++j) parent_joint[std::size_t(m.joints[j].child)] = int(j);
  auto allowed = [&](int a, int b) {
    for (auto [x, y] : m.allowed_pairs)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
  };
  std::vector<std::vector<formats::LinkSphere>> by_link(m.links.size());
  for (const auto& s : spheres)
    if (s.link >= 0 && std::size_t(s.link) < by_link.size()) by_link[std::size_t(s.link)].push_back(s);
  Eigen::VectorXd mid = (kin.lower() + kin.upper()) / 2;
  std::mt19937_64 rng(7);
  std::vector<Eigen::Isometry3d> poses;
  std::vector<int> path;
  std::vector<char> a_side;
  const int nl = int(m.links.size());
  for (int a = 0; a < nl; ++a)
    for (int b = a + 1; b < nl; ++b) {
      if (m.links[std::size_t(a)].collision.empty() || m.links[std::size_t(b)].collision.empty()) continue;
      if (by_link[std::size_t(a)].empty() || by_link[std::size_t(b)].empty() || allowed(a, b)) continue;
      if (!moving[std::size_t(a)] && !moving[std::size_t(b)]) continue;
      tree_path(m, parent_joint, a, b, path, a_side);
      std::vector<int> joints;
      std::vector<char> moves_a;
      bool usable = true;
      for (std::size_t i = 0; i < path.size(); ++i) {
        const Joint& j = m.joints[std::size_t(path[i])];
        if (j.type == JointType::Fixed) continue;
        usable &= j.type == JointType::Revolute && j.mimic < 0 && kin.chain_slot(path[i]) >= 0 && j.upper > j.lower;
        joints.push_back(path[i]);
        moves_a.push_back(a_side[i]);
      }
      if (!usable || joints.empty() || joints.size() > 2) continue;
      // Worth a table only where the spheres cannot prove the pair apart somewhere in range.
      bool overlap = false;
      Eigen::VectorXd q = mid;
      for (int s = 0; s < o.overlap_samples && !overlap; ++s) {
        for (int j : joints) {
          const Joint& jj = m.joints[std::size_t(j)];
          q[kin.chain_slot(j)] = std::uniform_real_distribution<double>(jj.lower, jj.upper)(rng);
        }
        kin.link_poses(q, poses);
        overlap = spheres_overlap(by_link[std::size_t(a)], by_link[std::size_t(b)], poses[std::size_t(a)], poses[std::size_t(b)]);
      }
      if (!overlap) continue;
      formats::SelfDistanceTable t;
      t.link_a = a;
      t.link_b = b;
      for (std::size_t k = 0; k < joints.size(); ++k) {
        const Joint& j = m.joints[std::size_t(joints[k])];
        t.joints[k] = joints[k];
        t.lower[k] = j.lower;
        t.count[k] = std::max(2, int(std::ceil((j.upper - j.lower) / o.step)) + 1);
        t.step[k] = (j.upper - j.lower) / (t.count[k] - 1);
        t.slope[k] = slope_bound(m, parent_joint, moves_a[k] ? a : b, joints[k], by_link[std::size_t(moves_a[k] ? a : b)]);
      }
      t.distance.resize(std::size_t(t.count[0]) * std::size_t(t.count[1]));
      detail::parallel_for(t.distance.size(), o.threads, [&](std::size_t n) {
        Eigen::VectorXd qn = mid;
        const std::size_t i0 = n / std::size_t(t.count[1]), i1 = n % std::size_t(t.count[1]);
        qn[kin.chain_slot(t.joints[0])] = t.lower[0] + double(i0) * t.step[0];
        if (t.joints[1] >= 0) qn[kin.chain_slot(t.joints[1])] = t.lower[1] + double(i1) * t.step[1];
        t.distance[n] = round_down(exact.link_distance(qn, a, b));
      });
      out.push_back(std::move(t));
    }
  return out;
}

}  // namespace dmgplace::tools
