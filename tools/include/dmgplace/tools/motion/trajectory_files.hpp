#pragma once
// Timed trajectories as files: our JSON (time, positions, velocities, accelerations as arrays)
// and MoveIt's trajectory_msgs/JointTrajectory YAML (joint_names; points with positions,
// velocities, accelerations and time_from_start {sec, nanosec}), which MoveIt and ros2_control
// load as is.
#include <string>
#include <vector>

#include "dmgplace/runtime/motion/trajectory.hpp"

namespace dmgplace::tools {

enum class TrajectoryFormat { Json, MoveIt };
// "json" or "moveit"; dmgplace::Error naming `option` otherwise.
TrajectoryFormat parse_trajectory_format(const std::string& text, const std::string& option);

// {"duration": s, "time": [...], "positions": [[...], ...], "velocities": ..., "accelerations": ...}
std::string trajectory_json_text(const runtime::Trajectory& t, int indent = -1);
std::string moveit_trajectory_yaml(const runtime::Trajectory& t, const std::vector<std::string>& joint_names);

}  // namespace dmgplace::tools
