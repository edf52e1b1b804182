#include "dmgplace/runtime/placement/retreat.hpp"

#include <cmath>
#include <random>

#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/robot/ik.hpp"

namespace dmgplace::runtime {

Retreat plan_retreat(const Kinematics& kin, const ExactChecker& released, const Eigen::VectorXd& q_place,
                     const Eigen::Vector3d& direction, double distance, double resolution, const ValidityFn& clear) {
  Retreat out;
  out.path.push_back(std::vector<double>(q_place.data(), q_place.data() + q_place.size()));
  if (!released.is_free(q_place)) {
    out.reason = "the hand collides with the placed object or the scene at release: " + released.check(q_place).contact;
    return out;
  }
  if (clear && clear(q_place)) {  // the open hand already lets go of the object: no withdrawal needed
    out.ok = true;
    return out;
  }
  IkOptions opt;
  opt.max_restarts = 0;
  const IkSolver ik(kin, opt);
  std::mt19937_64 rng(0);
  const Eigen::Isometry3d tcp = kin.tip_pose(q_place);
  const int steps = std::max(1, int(std::ceil(distance / 0.01)));
  Eigen::VectorXd q = q_place;
  auto valid = [&](const Eigen::VectorXd& c) { return released.is_free(c); };
  for (int s = 1; s <= steps; ++s) {
    Eigen::Isometry3d target = tcp;
    target.translation() += direction.normalized() * (distance * s / steps);
    const IkResult r = ik.solve(target, q, rng);
    if (!r.success || (r.q - q).cwiseAbs().maxCoeff() > 0.3) {
      out.reason = "no continuous arm motion withdraws the hand";
      return out;
    }
    if (!segment_valid(q, r.q, resolution, valid)) {
      out.reason = "withdrawing the hand collides: " + released.check(r.q).contact;
      return out;
    }
    q = r.q;
    out.path.push_back(std::vector<double>(q.data(), q.data() + q.size()));
    if (clear && clear(q)) {
      out.ok = true;
      return out;
    }
  }
  out.ok = !clear;
  if (!out.ok) out.reason = "the hand still touches the object after withdrawing " + std::to_string(distance) + " m";
  return out;
}

}  // namespace dmgplace::runtime
