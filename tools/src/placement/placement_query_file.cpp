#include "dmgplace/tools/placement/placement_query_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/yaml_file.hpp"

namespace dmgplace::tools {
namespace {
using runtime::ObjectiveTerm;
using runtime::PlacementOptions;

std::vector<double> numbers(const YAML::Node& n, std::size_t count, const std::string& file, const std::string& what) {
  if (!n.IsSequence() || n.size() != count)
    throw Error(file, what, "expected a list of " + std::to_string(count) + " numbers");
  std::vector<double> v = n.as<std::vector<double>>();
  for (double x : v)
    if (!std::isfinite(x)) throw Error(file, what, "not a finite number");
  return v;
}

// A YAML number that must be finite: .nan or .inf in a query would poison the search silently.
double real(const YAML::Node& n, const std::string& file, const std::string& what) {
  const double v = n.as<double>();
  if (!std::isfinite(v)) throw Error(file, what, "not a finite number");
  return v;
}

Eigen::Vector3d vec3(const YAML::Node& n, const std::string& file, const std::string& what) {
  const auto v = numbers(n, 3, file, what);
  return {v[0], v[1], v[2]};
}

void read_options(const YAML::Node& n, PlacementOptions& o, const std::string& file) {
  if (!n.IsMap()) throw Error(file, "options", "expected a map of option: value");
  const std::map<std::string, std::function<void(const YAML::Node&)>> setters = {
      {"max_depth", [&](const YAML::Node& v) { o.max_depth = v.as<int>(); }},
      {"ucb_c", [&](const YAML::Node& v) { o.ucb_c = real(v, file, "options.ucb_c"); }},
      {"goal_iterations", [&](const YAML::Node& v) { o.goal_iterations = v.as<int>(); }},
      {"p_accept", [&](const YAML::Node& v) { o.p_accept = real(v, file, "options.p_accept"); }},
      {"grasp_tries", [&](const YAML::Node& v) { o.grasp_tries = v.as<int>(); }},
      {"lift", [&](const YAML::Node& v) { o.lift = real(v, file, "options.lift"); }},
      {"ik_restarts", [&](const YAML::Node& v) { o.ik_restarts = v.as<int>(); }},
      {"motion_resolution", [&](const YAML::Node& v) { o.motion_resolution = real(v, file, "options.motion_resolution"); }},
      {"threads", [&](const YAML::Node& v) { o.threads = v.as<int>(); }},
      {"slice_iterations", [&](const YAML::Node& v) { o.slice_iterations = v.as<int>(); }},
      {"max_open_goals", [&](const YAML::Node& v) { o.max_open_goals = v.as<int>(); }},
      {"optimize_locally", [&](const YAML::Node& v) { o.optimize_locally = v.as<bool>(); }},
      {"local_step", [&](const YAML::Node& v) { o.local_step = real(v, file, "options.local_step"); }},
      {"local_iterations", [&](const YAML::Node& v) { o.local_iterations = v.as<int>(); }},
      {"check_retreat", [&](const YAML::Node& v) { o.check_retreat = v.as<bool>(); }},
      {"retreat_distance", [&](const YAML::Node& v) { o.retreat_distance = real(v, file, "options.retreat_distance"); }},
      {"tie_tolerance", [&](const YAML::Node& v) { o.tie_tolerance = real(v, file, "options.tie_tolerance"); }},
  };
  for (const auto& kv : n) {
    const auto key = kv.first.as<std::string>();
    auto it = setters.find(key);
    if (it == setters.end()) throw Error(file, "options." + key, "unknown option");
    try {
      it->second(kv.second);
    } catch (const YAML::Exception&) {
      throw Error(file, "options." + key, "wrong type");
    }
  }
}

ObjectiveTerm read_term(const YAML::Node& n, const std::string& file, std::size_t index) {
  const std::string where = "objective[" + std::to_string(index) + "]";
  if (!n.IsMap() || !n["term"]) throw Error(file, where, "expected {term: clearance|depth|distance|upright, ...}");
  ObjectiveTerm t;
  const auto name = n["term"].as<std::string>();
  const auto kind = runtime::parse_objective_kind(name);
  if (!kind) throw Error(file, where + ".term", "unknown term '" + name + "' (clearance, depth, distance, upright)");
  t.kind = *kind;
  if (n["weight"]) t.weight = real(n["weight"], file, where + ".weight");
  const char* key = t.kind == ObjectiveTerm::Kind::Depth      ? "direction"
                    : t.kind == ObjectiveTerm::Kind::Distance ? "target"
                    : t.kind == ObjectiveTerm::Kind::Upright  ? "axis"
                                                              : nullptr;
  if (key) {
    if (!n[key]) throw Error(file, where, std::string("term '") + name + "' needs '" + key + "' [x, y, z]");
    t.vector = vec3(n[key], file, where + "." + key);
  }
  return t;
}
}  // namespace

PlacementQueryFile read_placement_query(const std::filesystem::path& path, const std::filesystem::path& artifact_dir) {
  const std::string file = path.string();
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap()) throw Error(file, "", "expected a map (robot, object, environment, start, initial_grasp, ...)");
  PlacementQueryFile f;
  f.path = path;
  const auto dir = artifact_dir.empty() ? path.parent_path() : artifact_dir;
  try {
    for (auto [key, dst] : {std::pair{"robot", &f.robot}, std::pair{"object", &f.object}, std::pair{"environment", &f.environment}}) {
      if (!root[key]) throw Error(file, key, "missing (path of the artifact, relative to the query file)");
      const std::filesystem::path p = root[key].as<std::string>();
      *dst = p.is_absolute() ? p : dir / p;
    }
    const YAML::Node start = root["start"];
    if (!start) throw Error(file, "start", "missing (the arm's joint values)");
    if (start.IsSequence()) {
      for (std::size_t i = 0; i < start.size(); ++i)
        f.start_list.push_back(real(start[i], file, "start[" + std::to_string(i) + "]"));
    } else if (start.IsMap()) {
      for (const auto& kv : start) {
        const auto name = kv.first.as<std::string>();
        f.start_named[name] = real(kv.second, file, "start." + name);
      }
    } else {
      throw Error(file, "start", "expected a list of joint values or a map joint: value");
    }
    const YAML::Node g = root["initial_grasp"];
    if (!g || !g["pose"]) throw Error(file, "initial_grasp", "missing {pose: [x, y, z, qx, qy, qz, qw]}");
    const auto p = numbers(g["pose"], 7, file, "initial_grasp.pose");
    Eigen::Quaterniond quat(p[6], p[3], p[4], p[5]);
    if (quat.norm() < 1e-6) throw Error(file, "initial_grasp.pose", "zero quaternion");
    f.query.g0 = Eigen::Translation3d(p[0], p[1], p[2]) * quat.normalized();
    if (g["opening"]) f.query.g0_opening = real(g["opening"], file, "initial_grasp.opening");
    if (root["volume"]) {
      const auto v = numbers(root["volume"], 6, file, "volume");
      if (v[0] > v[3] || v[1] > v[4] || v[2] > v[5]) throw Error(file, "volume", "min exceeds max");
      f.query.volume = Eigen::AlignedBox3d(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]));
    }
    if (root["objective"]) {
      const YAML::Node o = root["objective"];
      if (!o.IsSequence() || o.size() == 0) throw Error(file, "objective", "expected a non-empty list of terms");
      f.query.objective.clear();
      for (std::size_t i = 0; i < o.size(); ++i) f.query.objective.push_back(read_term(o[i], file, i));
    }
    if (root["time_limit"]) f.time_limit = root["time_limit"].as<double>();
    if (!(f.time_limit >= 0) || !std::isfinite(f.time_limit)) throw Error(file, "time_limit", "must be a finite number >= 0");
    if (root["seed"]) f.query.seed = root["seed"].as<std::uint64_t>();
    if (root["variant"]) {
      const auto name = root["variant"].as<std::string>();
      const auto v = runtime::parse_variant(name);
      if (!v) throw Error(file, "variant", "unknown variant '" + name + "' (full, random-grasp, no-regrasp)");
      f.query.variant = *v;
    }
    if (root["options"]) read_options(root["options"], f.query.options, file);
  } catch (const YAML::Exception& e) {
    throw Error(file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1), std::string("malformed query: ") + e.msg);
  }
  return f;
}

Eigen::VectorXd resolve_start(const PlacementQueryFile& f, const runtime::Kinematics& kin) {
  const std::string file = f.path.string();
  Eigen::VectorXd q(kin.dof());
  if (!f.start_list.empty() || f.start_named.empty()) {
    if (int(f.start_list.size()) != kin.dof())
      throw Error(file, "start", "has " + std::to_string(f.start_list.size()) + " values, the arm has " +
                                     std::to_string(kin.dof()) + " joints");
    for (int i = 0; i < kin.dof(); ++i) q[i] = f.start_list[std::size_t(i)];
  } else {
    for (int i = 0; i < kin.dof(); ++i) {
      const auto& name = kin.joint_names()[std::size_t(i)];
      auto it = f.start_named.find(name);
      if (it == f.start_named.end()) throw Error(file, "start", "no value for joint '" + name + "'");
      q[i] = it->second;
    }
  }
  if (!q.allFinite()) throw Error(file, "start", "not finite (NaN or infinity)");
  if (!kin.within_limits(q, 1e-6)) throw Error(file, "start", "outside the arm's joint limits");
  return q;
}

}  // namespace dmgplace::tools
