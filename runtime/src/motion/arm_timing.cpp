#include "dmgplace/runtime/motion/arm_timing.hpp"

namespace dmgplace::runtime {

JointLimits arm_joint_limits(const Kinematics& kin) {
  JointLimits limits;
  limits.velocity.assign(std::size_t(kin.dof()), kDefaultVelocityLimit);
  limits.acceleration.assign(std::size_t(kin.dof()), kDefaultAccelerationLimit);
  const auto& joints = kin.model().joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const int slot = kin.chain_slot(int(j));
    if (slot < 0) continue;
    if (joints[j].velocity > 0) limits.velocity[std::size_t(slot)] = joints[j].velocity;
    if (joints[j].acceleration > 0) limits.acceleration[std::size_t(slot)] = joints[j].acceleration;
  }
  return limits;
}

Trajectory time_arm_path(const Kinematics& kin, const JointPath& path, const TimingOptions& options) {
  if (path.empty()) return {};
  return time_parameterize(path, arm_joint_limits(kin), options);
}

}  // namespace dmgplace::runtime
