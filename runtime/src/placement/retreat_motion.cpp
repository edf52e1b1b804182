#include "dmgplace/runtime/placement/retreat_motion.hpp"

#include "dmgplace/runtime/motion/segment_check.hpp"

namespace dmgplace::runtime {

bool retreat_state_free(const RetreatScene& s, const Eigen::VectorXd& q) {
  if (!s.arm->is_free(q)) return false;
  thread_local std::vector<Eigen::Isometry3d> poses;
  s.kin->link_poses(q, poses);
  for (const auto& sp : *s.spheres) {
    const Eigen::Vector3d c = poses[std::size_t(sp.link)] * sp.center;
    // A sphere clear of the object's ball keeps its part of the link clear of the object.
    if ((c - s.object_center).norm() < sp.radius + s.object_radius) return s.placed->is_free(q);
  }
  return true;
}

JointPath retrace_approach(const RetreatScene& s, const Eigen::VectorXd& from, const JointPath& approach,
                           double resolution) {
  if (approach.empty()) return {};
  const ValidityFn valid = [&s](const Eigen::VectorXd& q) { return retreat_state_free(s, q); };
  const auto vec = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
  };
  // back_free: how many of the approach's first waypoints lead back to its start, every segment free.
  std::size_t back_free = 0;
  if (valid(vec(approach[0]))) {
    back_free = 1;
    while (back_free < approach.size() &&
           segment_valid(vec(approach[back_free]), vec(approach[back_free - 1]), resolution, valid))
      ++back_free;
  }
  for (std::size_t j = back_free; j-- > 0;) {
    if (!segment_valid(from, vec(approach[j]), resolution, valid)) continue;
    JointPath out{std::vector<double>(from.data(), from.data() + from.size())};
    for (std::size_t k = j + 1; k-- > 0;) out.push_back(approach[k]);
    return out;
  }
  return {};
}

JointPath plan_retreat_motion(const RetreatScene& s, const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                              const RetreatBudget& budget, MotionTree* tree) {
  return plan_free_motion(
      *s.kin, [&s](const Eigen::VectorXd& q) { return retreat_state_free(s, q); }, from, to, budget, tree);
}

}  // namespace dmgplace::runtime
