#include "dmgplace/tools/io/joint_limits_reader.hpp"

#include <cmath>
#include <optional>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/yaml_file.hpp"

namespace dmgplace::tools {
namespace {

double positive(const YAML::Node& n, const std::string& file, const std::string& where) {
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw Error(file, where, "expected a number");
  }
  if (!std::isfinite(v) || v <= 0) throw Error(file, where, "must be finite and > 0");
  return v;
}

bool flag(const YAML::Node& n, const std::string& file, const std::string& where) {
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    throw Error(file, where, "expected true or false");
  }
}

// A `has_X: true` needs its value (finite, > 0); `has_X: false` (or absent) leaves the URDF's.
std::optional<double> given(const YAML::Node& entry, const char* has, const char* value, const std::string& file,
                            const std::string& where) {
  if (!entry[has] || !flag(entry[has], file, where + "." + has)) return std::nullopt;
  if (!entry[value]) throw Error(file, where, std::string(has) + " is true but " + value + " is missing");
  return positive(entry[value], file, where + "." + value);
}

void apply_position(Joint& j, const YAML::Node& entry, const std::string& file, const std::string& where) {
  if (!entry["has_position_limits"] || !flag(entry["has_position_limits"], file, where + ".has_position_limits"))
    return;
  if (j.type != JointType::Revolute && j.type != JointType::Prismatic)
    throw Error(file, where, "position limits on a joint without URDF limits");
  if (!entry["min_position"] || !entry["max_position"])
    throw Error(file, where, "has_position_limits is true but min_position or max_position is missing");
  double lo = 0, hi = 0;
  try {
    lo = entry["min_position"].as<double>();
    hi = entry["max_position"].as<double>();
  } catch (const YAML::Exception&) {
    throw Error(file, where, "min_position and max_position must be numbers");
  }
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi)
    throw Error(file, where, "min_position > max_position or not finite");
  if (lo < j.lower - 1e-9 || hi > j.upper + 1e-9) throw Error(file, where, "position limits wider than the URDF's");
  j.lower = lo;
  j.upper = hi;
}

}  // namespace

JointLimitsFile apply_joint_limits(RobotModel& model, const std::filesystem::path& path) {
  const std::string file = path.string();
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap()) throw Error(file, "", "expected a map with joint_limits");
  require_known_keys(root, {"joint_limits", "default_velocity_scaling_factor", "default_acceleration_scaling_factor"},
                     file, "");
  JointLimitsFile out;
  for (const char* k : {"default_velocity_scaling_factor", "default_acceleration_scaling_factor"})
    if (root[k])
      out.notes.push_back(std::string(k) + " is not used: the query's velocity_scaling/acceleration_scaling apply");
  const YAML::Node limits = root["joint_limits"];
  if (!limits || !limits.IsMap()) throw Error(file, "joint_limits", "expected a map of joint name: limits");
  for (const auto& kv : limits) {
    const std::string name = kv.first.as<std::string>();
    const std::string where = "joint_limits." + name;
    const int index = model.joint_index(name);
    if (index < 0) throw Error(file, where, "no joint '" + name + "' in the robot");
    const YAML::Node& entry = kv.second;
    if (!entry.IsMap()) throw Error(file, where, "expected a map of limits");
    require_known_keys(
        entry,
        {"has_velocity_limits", "max_velocity", "has_acceleration_limits", "max_acceleration", "has_position_limits",
         "min_position", "max_position", "has_jerk_limits", "max_jerk", "has_effort_limits", "max_effort"},
        file, where);
    Joint& j = model.joints[std::size_t(index)];
    if (const auto v = given(entry, "has_velocity_limits", "max_velocity", file, where)) j.velocity = *v;
    if (const auto a = given(entry, "has_acceleration_limits", "max_acceleration", file, where)) j.acceleration = *a;
    apply_position(j, entry, file, where);
    for (const char* k : {"has_jerk_limits", "has_effort_limits"})
      if (entry[k] && flag(entry[k], file, where + "." + k))
        out.notes.push_back(where + "." + k + " is not used: trajectories are limited in velocity and acceleration");
  }
  return out;
}

}  // namespace dmgplace::tools
