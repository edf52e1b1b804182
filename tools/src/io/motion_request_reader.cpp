#include "dmgplace/tools/io/motion_request_reader.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/yaml_file.hpp"

namespace dmgplace::tools {

MotionRequest read_motion_request(const std::filesystem::path& path) {
  const std::string file = path.string();
  const YAML::Node root = load_yaml_file(path);
  MotionRequest r;
  try {
    const YAML::Node js = root["start_state"]["joint_state"];
    if (!js || !js["name"] || !js["position"]) throw Error(file, "start_state.joint_state", "missing name/position");
    const auto names = js["name"].as<std::vector<std::string>>();
    const auto pos = js["position"].as<std::vector<double>>();
    if (names.size() != pos.size())
      throw Error(file, "start_state.joint_state", "name and position lists differ in length");
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (!std::isfinite(pos[i])) throw Error(file, "start_state.joint_state." + names[i], "not a finite number");
      r.start[names[i]] = pos[i];
    }
    const YAML::Node goals = root["goal_constraints"];
    if (!goals || !goals.IsSequence() || goals.size() == 0) throw Error(file, "goal_constraints", "missing or empty");
    const YAML::Node jc = goals[0]["joint_constraints"];
    if (!jc || !jc.IsSequence() || jc.size() == 0)
      throw Error(file, "goal_constraints[0].joint_constraints", "missing: only joint-space goals are supported");
    for (const auto& c : jc) {
      if (!c["joint_name"] || !c["position"])
        throw Error(file, "goal_constraints[0].joint_constraints", "entry without joint_name/position");
      const double v = c["position"].as<double>();
      const auto name = c["joint_name"].as<std::string>();
      if (!std::isfinite(v)) throw Error(file, "goal joint " + name, "not a finite number");
      r.goal[name] = v;
    }
    if (root["allowed_planning_time"]) r.allowed_planning_time = root["allowed_planning_time"].as<double>();
  } catch (const YAML::Exception& e) {
    throw Error(file, "", std::string("malformed request: ") + e.what());
  }
  return r;
}

}  // namespace dmgplace::tools
