#pragma once
// MoveIt's joint_limits.yaml (a MoveIt config package's config/joint_limits.yaml): per joint
// velocity and acceleration limits, and optionally tighter position limits. They override the
// URDF's, as MoveIt does; position limits may only narrow the URDF's range.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_model.hpp"

namespace dmgplace::tools {

struct JointLimitsFile {
  std::vector<std::string> notes;  // what was read but is not used (for the caller to report)
};

// Applies the file to `model` (joints named there must exist in it). dmgplace::Error naming the
// file and the joint's key on a malformed file, an unknown joint or key, or a limit that is not
// finite and > 0.
JointLimitsFile apply_joint_limits(RobotModel& model, const std::filesystem::path& file);

}  // namespace dmgplace::tools
