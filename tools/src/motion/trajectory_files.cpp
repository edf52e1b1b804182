#include "dmgplace/tools/motion/trajectory_files.hpp"

#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

void yaml_list(std::ostringstream& o, const std::vector<double>& v) {
  o << '[';
  for (std::size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
  o << ']';
}

// A single-quoted YAML scalar: whatever a joint is called, it stays one string.
std::string yaml_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

}  // namespace

TrajectoryFormat parse_trajectory_format(const std::string& text, const std::string& option) {
  if (text == "json") return TrajectoryFormat::Json;
  if (text == "moveit") return TrajectoryFormat::MoveIt;
  throw Error(option, "", "unknown trajectory format '" + text + "' (json, moveit)");
}

std::string trajectory_json_text(const runtime::Trajectory& t, int indent) {
  nlohmann::ordered_json j;
  j["duration"] = t.duration();
  j["time"] = t.time;
  j["positions"] = t.positions;
  j["velocities"] = t.velocities;
  j["accelerations"] = t.accelerations;
  return j.dump(indent);
}

std::string moveit_trajectory_yaml(const runtime::Trajectory& t, const std::vector<std::string>& joint_names) {
  std::ostringstream o;
  o << std::setprecision(17);
  o << "header:\n  stamp:\n    sec: 0\n    nanosec: 0\n  frame_id: ''\njoint_names: [";
  for (std::size_t i = 0; i < joint_names.size(); ++i) o << (i ? ", " : "") << yaml_quoted(joint_names[i]);
  o << "]\npoints:" << (t.time.empty() ? " []\n" : "\n");
  for (std::size_t k = 0; k < t.time.size(); ++k) {
    // time_from_start as ROS's Duration: whole seconds and nanoseconds, rounded to the nanosecond.
    const long long ns = std::llround(t.time[k] * 1e9);
    o << "  - positions: ";
    yaml_list(o, t.positions[k]);
    o << "\n    velocities: ";
    yaml_list(o, t.velocities[k]);
    o << "\n    accelerations: ";
    yaml_list(o, t.accelerations[k]);
    o << "\n    effort: []\n    time_from_start:\n      sec: " << ns / 1000000000
      << "\n      nanosec: " << ns % 1000000000 << '\n';
  }
  return o.str();
}

}  // namespace dmgplace::tools
