#pragma once
// The arm chain's limits for timing its paths: velocities from the URDF (or joint_limits.yaml),
// accelerations from joint_limits.yaml (`bake-robot --joint-limits`), defaults where neither
// gave one. The acceleration default is MoveIt's time-parameterisation default.
#include "dmgplace/runtime/motion/trajectory.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::runtime {

inline constexpr double kDefaultVelocityLimit = 1.0;      // rad/s (m/s) where the robot gives none
inline constexpr double kDefaultAccelerationLimit = 1.0;  // rad/s^2 (m/s^2) where the robot gives none

// One entry per chain joint, in q's order.
JointLimits arm_joint_limits(const Kinematics& kin);

// Times a path of the arm (time_parameterize with the arm's limits); an empty path gives an
// empty trajectory.
Trajectory time_arm_path(const Kinematics& kin, const JointPath& path, const TimingOptions& options);

}  // namespace dmgplace::runtime
