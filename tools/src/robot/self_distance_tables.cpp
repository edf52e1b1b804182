#include "dmgplace/tools/robot/self_distance_tables.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>

#include "../system/parallel_for.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/system/progress.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::tools {
namespace {

// Joints from `link` up to the root, nearest first.
std::vector<int> joints_to_root(const RobotModel& m, const std::vector<int>& parent_joint, int link) {
  std::vector<int> out;
  for (int l = link; parent_joint[std::size_t(l)] >= 0 && out.size() <= m.joints.size();
       l = m.joints[std::size_t(parent_joint[std::size_t(l)])].parent)
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

// Largest distance from joint k's axis of any point of `link`'s spheres: how fast turning k moves
// them, so the pair's distance changes no faster (the table's slope for k). The link's spheres are
// carried up to k's frame as balls: exactly through fixed joints; through another revolute joint,
// each as the ball that holds it at every angle of that joint. The distance from k's axis (not its
// origin) is what turning k moves a point by: a point near the axis barely moves.
double slope_bound(const RobotModel& m, const std::vector<int>& parent_joint, int link, int k,
                   const std::vector<formats::LinkSphere>& link_spheres) {
  struct Ball {
    Eigen::Vector3d center;
    double radius;
  };
  std::vector<Ball> balls;
  for (const auto& s : link_spheres) balls.push_back({s.center, s.radius});
  for (int l = link; parent_joint[std::size_t(l)] >= 0;) {
    const int j = parent_joint[std::size_t(l)];
    const Joint& joint = m.joints[std::size_t(j)];
    if (j == k) {  // the balls are in k's frame, its axis through the origin
      const Eigen::Vector3d a = joint.axis.normalized();
      double most = 0;
      for (const Ball& b : balls) most = std::max(most, (b.center - b.center.dot(a) * a).norm() + b.radius);
      return most;
    }
    if (joint.type == JointType::Prismatic) break;  // no rigid reach (tables take revolute joints only)
    if (joint.type != JointType::Fixed) {
      // Turning about this joint's axis sweeps a ball around a circle: the ball about the
      // circle's center (on the axis) reaching the circle's radius farther holds it at any angle.
      const Eigen::Vector3d a = joint.axis.normalized();
      for (Ball& b : balls) {
        const Eigen::Vector3d along = b.center.dot(a) * a;
        b.radius += (b.center - along).norm();
        b.center = along;
      }
    }
    for (Ball& b : balls) b.center = joint.origin * b.center;
    l = joint.parent;
  }
  return std::numeric_limits<double>::infinity();  // not reached (k is not above the link), or past a slide
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

// Lattice nodes: every `stride`-th index, and the last.
std::vector<std::size_t> lattice(std::size_t count, std::size_t stride) {
  std::vector<std::size_t> v;
  for (std::size_t i = 0; i < count; i += stride) v.push_back(i);
  if (v.back() != count - 1) v.push_back(count - 1);
  return v;
}

// The lattice cell holding index i: its two lattice indices (the same one on a lattice node).
std::pair<std::size_t, std::size_t> cell(const std::vector<std::size_t>& l, std::size_t i) {
  const auto hi = std::lower_bound(l.begin(), l.end(), i);
  return {*hi == i || hi == l.begin() ? *hi : *(hi - 1), *hi};
}

// Fills table t (grid already sized): exact on the coarse lattice, then each other node from its
// coarse cell's Lipschitz bound when that is far from contact, exactly otherwise. Every node
// computed keeps where its links were closest: the next node along its row starts FCL from that
// pair, and the lattice's witnesses serve the nodes of their cells. Rows go in parallel, each in
// order from its own first node, so the values are the same on any thread count.
class TableFill {
 public:
  TableFill(formats::SelfDistanceTable& t, const runtime::Kinematics& kin, const runtime::ExactChecker& exact, int a,
            int b, const Eigen::VectorXd& mid, const SelfTableOptions& o, ProgressReporter& progress)
      : t_(t), kin_(kin), exact_(exact), a_(a), b_(b), mid_(mid), o_(o), progress_(progress),
        c1_(std::size_t(t.count[1])), l0_(lattice(std::size_t(t.count[0]), std::size_t(o.coarse_stride))),
        l1_(lattice(c1_, std::size_t(o.coarse_stride))), witness_(std::size_t(t.count[0]) * c1_) {}

  void run() {
    t_.distance.assign(witness_.size(), 0.0f);
    progress_.add_total(witness_.size());
    lattice_pass();
    refine_pass(bound_pass());
  }

 private:
  Eigen::VectorXd at(std::size_t i0, std::size_t i1) const {
    Eigen::VectorXd qn = mid_;
    qn[kin_.chain_slot(t_.joints[0])] = t_.lower[0] + double(i0) * t_.step[0];
    if (t_.joints[1] >= 0) qn[kin_.chain_slot(t_.joints[1])] = t_.lower[1] + double(i1) * t_.step[1];
    return qn;
  }

  void lattice_pass() {
    detail::parallel_for(l0_.size(), o_.threads, [&](std::size_t r) {
      const std::size_t i0 = l0_[r];
      for (std::size_t k = 0; k < l1_.size(); ++k) {
        const std::size_t n = i0 * c1_ + l1_[k];
        const std::vector<runtime::LinkWitness> near =
            k == 0 ? std::vector<runtime::LinkWitness>{} : std::vector{witness_[i0 * c1_ + l1_[k - 1]]};
        t_.distance[n] = round_down(exact_.link_distance_within(at(i0, l1_[k]), a_, b_, 0.0, near, &witness_[n]));
        progress_.done(1);
      }
    });
  }

  // Per node: the enclosing lattice cell's corners bound it (each corner's distance minus what
  // the joints can change it by on the way). Stores the bounds far from contact; the other nodes.
  std::vector<std::size_t> bound_pass() {
    std::vector<char> coarse(witness_.size(), 0);
    for (auto i0 : l0_)
      for (auto i1 : l1_) coarse[i0 * c1_ + i1] = 1;
    std::vector<std::size_t> refine;
    std::size_t bounded = 0;
    for (std::size_t n = 0; n < witness_.size(); ++n) {
      if (coarse[n]) continue;
      const std::size_t i0 = n / c1_, i1 = n % c1_;
      const auto [a0, b0] = cell(l0_, i0);
      const auto [a1, b1] = cell(l1_, i1);
      double lb = -std::numeric_limits<double>::infinity();
      for (auto k0 : {a0, b0})
        for (auto k1 : {a1, b1}) {
          const double loss = t_.slope[0] * t_.step[0] * std::abs(double(k0) - double(i0)) +
                              (t_.joints[1] >= 0 ? t_.slope[1] * t_.step[1] * std::abs(double(k1) - double(i1)) : 0.0);
          lb = std::max(lb, double(t_.distance[k0 * c1_ + k1]) - loss);
        }
      if (lb >= o_.exact_below) {
        t_.distance[n] = round_down(lb);
        ++bounded;
      } else {
        refine.push_back(n);
      }
    }
    progress_.done(bounded);
    return refine;
  }

  // Each node from its cell's lattice corners' witnesses and the node's before it in its row.
  void refine_pass(const std::vector<std::size_t>& refine) {
    std::vector<std::size_t> row_start{0};
    for (std::size_t k = 1; k <= refine.size(); ++k)
      if (k == refine.size() || refine[k] / c1_ != refine[k - 1] / c1_) row_start.push_back(k);
    detail::parallel_for(row_start.size() - 1, o_.threads, [&](std::size_t r) {
      for (std::size_t k = row_start[r]; k < row_start[r + 1]; ++k) {
        const std::size_t n = refine[k], i0 = n / c1_, i1 = n % c1_;
        const auto [a0, b0] = cell(l0_, i0);
        const auto [a1, b1] = cell(l1_, i1);
        std::vector<runtime::LinkWitness> near{witness_[a0 * c1_ + a1], witness_[a0 * c1_ + b1],
                                               witness_[b0 * c1_ + a1], witness_[b0 * c1_ + b1]};
        if (i1 > 0) near.push_back(witness_[n - 1]);  // computed before (or empty where bounded)
        t_.distance[n] = round_down(exact_.link_distance_within(at(i0, i1), a_, b_, o_.tolerance, near, &witness_[n]));
        progress_.done(1);
      }
    });
  }

  formats::SelfDistanceTable& t_;
  const runtime::Kinematics& kin_;
  const runtime::ExactChecker& exact_;
  const int a_, b_;
  const Eigen::VectorXd& mid_;
  const SelfTableOptions& o_;
  ProgressReporter& progress_;
  const std::size_t c1_;
  const std::vector<std::size_t> l0_, l1_;
  std::vector<runtime::LinkWitness> witness_;
};
}  // namespace

std::vector<formats::SelfDistanceTable> build_self_distance_tables(const runtime::Kinematics& kin,
                                                                   const std::vector<formats::LinkSphere>& spheres,
                                                                   const SelfTableOptions& o) {
  std::vector<formats::SelfDistanceTable> out;
  if (!o.enabled) return out;
  if (o.coarse_stride < 1 || !(o.exact_below >= 0) || !(o.tolerance >= 0))
    throw Error("self-distance tables", "options", "coarse stride >= 1, exact_below >= 0, tolerance >= 0");
  ProgressReporter progress(o.progress, "self-distance tables");
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
        overlap = spheres_overlap(by_link[std::size_t(a)], by_link[std::size_t(b)], poses[std::size_t(a)],
                                  poses[std::size_t(b)]);
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
        t.slope[k] =
            slope_bound(m, parent_joint, moves_a[k] ? a : b, joints[k], by_link[std::size_t(moves_a[k] ? a : b)]);
      }
      TableFill(t, kin, exact, a, b, mid, o, progress).run();
      out.push_back(std::move(t));
    }
  return out;
}

}  // namespace dmgplace::tools
