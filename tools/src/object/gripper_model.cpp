#include "dmgplace/tools/object/gripper_model.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/yaml_file.hpp"

namespace dmgplace::tools {
namespace {

double positive(const YAML::Node& n, const std::string& file, const std::string& key, double fallback,
                bool allow_zero = false) {
  if (!n) return fallback;
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw Error(file, key, "not a number");
  }
  if (!std::isfinite(v) || v < 0 || (!allow_zero && v == 0)) throw Error(file, key, "must be a positive finite number");
  return v;
}

Eigen::Vector3d vec3(const YAML::Node& n, const std::string& file, const std::string& key,
                     const Eigen::Vector3d& fallback) {
  if (!n) return fallback;
  if (!n.IsSequence() || n.size() != 3) throw Error(file, key, "expected a list of 3 numbers");
  Eigen::Vector3d v;
  try {
    for (int i = 0; i < 3; ++i) v[i] = n[i].as<double>();
  } catch (const YAML::Exception&) {
    throw Error(file, key, "expected a list of 3 numbers");
  }
  if (!v.allFinite()) throw Error(file, key, "not finite");
  return v;
}

void only_keys(const YAML::Node& n, const std::set<std::string>& keys, const std::string& file,
               const std::string& where) {
  if (!n) return;
  if (!n.IsMap()) throw Error(file, where, "expected a mapping");
  for (const auto& kv : n) {
    const auto k = kv.first.as<std::string>();
    if (!keys.contains(k)) throw Error(file, where.empty() ? k : where + "." + k, "unknown key");
  }
}

}  // namespace

formats::GripperModel default_gripper() { return formats::GripperModel{}; }

formats::GripperModel load_gripper_yaml(const std::filesystem::path& path) {
  const std::string file = path.string();
  const YAML::Node root = load_yaml_file(path);
  only_keys(root, {"name", "max_opening", "finger", "palm", "contact_tolerance"}, file, "");
  only_keys(root["finger"], {"length", "width", "thickness", "tip_offset"}, file, "finger");
  only_keys(root["palm"], {"size", "center"}, file, "palm");
  formats::GripperModel g = default_gripper();
  g.max_opening = positive(root["max_opening"], file, "max_opening", g.max_opening);
  // Missing sections read as empty maps (yaml-cpp throws when indexing an absent node).
  const YAML::Node f = root["finger"] ? root["finger"] : YAML::Node(YAML::NodeType::Map);
  const YAML::Node palm = root["palm"] ? root["palm"] : YAML::Node(YAML::NodeType::Map);
  g.finger_length = positive(f["length"], file, "finger.length", g.finger_length);
  g.finger_width = positive(f["width"], file, "finger.width", g.finger_width);
  g.finger_thickness = positive(f["thickness"], file, "finger.thickness", g.finger_thickness);
  g.tip_offset = positive(f["tip_offset"], file, "finger.tip_offset", g.tip_offset, true);
  if (g.tip_offset > g.finger_length) throw Error(file, "finger.tip_offset", "longer than the finger");
  g.palm_size = vec3(palm["size"], file, "palm.size", g.palm_size);
  if (g.palm_size.minCoeff() <= 0) throw Error(file, "palm.size", "must be positive");
  g.palm_center = vec3(palm["center"], file, "palm.center", g.palm_center);
  g.contact_tolerance = positive(root["contact_tolerance"], file, "contact_tolerance", g.contact_tolerance, true);
  return g;
}

}  // namespace dmgplace::tools
