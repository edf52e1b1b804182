#pragma once
// MoveIt MotionPlanRequest YAML (as in MotionBenchMaker problems): the start joint state and a
// joint-space goal.
#include <filesystem>
#include <map>
#include <string>

namespace dmgplace::tools {

struct MotionRequest {
  std::map<std::string, double> start;  // every joint named in start_state.joint_state
  std::map<std::string, double> goal;   // goal_constraints[0].joint_constraints
  double allowed_planning_time = 0;
};

// Throws dmgplace::Error naming the file and the field.
MotionRequest read_motion_request(const std::filesystem::path& yaml);

}  // namespace dmgplace::tools
