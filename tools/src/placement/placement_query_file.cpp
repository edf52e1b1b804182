#include "dmgplace/tools/placement/placement_query_file.hpp"
#include "dmgplace/formats/pose_input.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/tools/io/yaml_file.hpp"

namespace dmgplace::tools {
namespace {
using runtime::ObjectiveTerm;
constexpr double kMaxTimeLimit = 1e6;  // s (11.6 days); also keeps the deadline's nanosecond count from overflowing
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

// A YAML integer in [lo, hi], or an error naming the option and its range.
long long integer(const YAML::Node& n, long long lo, long long hi, const std::string& file, const std::string& what) {
  long long v = 0;
  try {
    v = n.as<long long>();
  } catch (const YAML::Exception&) {
    throw Error(file, what + (yaml_line(n).empty() ? "" : " (" + yaml_line(n) + ")"), "expected an integer");
  }
  if (v < lo || v > hi)
    throw Error(file, what,
                runtime::number_text(v) + " is outside its range [" + runtime::number_text(lo) + ", " +
                    runtime::number_text(hi) + "]");
  return v;
}

double ranged(const YAML::Node& n, double lo, double hi, const std::string& file, const std::string& what) {
  const double v = real(n, file, what);
  if (v < lo || v > hi)
    throw Error(file, what,
                runtime::number_text(v) + " is outside its range [" + runtime::number_text(lo) + ", " +
                    runtime::number_text(hi) + "]");
  return v;
}

// Options by name from the runtime's table: a value outside its range is refused at parse time
// (a 2e9 IK restart count ignores any time limit; 100000 threads exhaust the process).
void read_options(const YAML::Node& n, PlacementOptions& o, const std::string& file) {
  if (!n.IsMap()) throw Error(file, "options", "expected a map of option: value");
  const auto& specs = runtime::placement_option_specs();
  for (const auto& kv : n) {
    const auto key = kv.first.as<std::string>();
    const auto it = std::find_if(specs.begin(), specs.end(), [&](const auto& s) { return key == s.name; });
    const std::string where = "options." + key;
    if (it == specs.end()) {
      std::string known;
      for (const auto& s : specs) known += (known.empty() ? "" : ", ") + std::string(s.name);
      throw Error(file, where + (yaml_line(kv.first).empty() ? "" : " (" + yaml_line(kv.first) + ")"),
                  "unknown option (expected one of: " + known + ")");
    }
    if (const auto* m = std::get_if<int PlacementOptions::*>(&it->member)) {
      o.*(*m) = int(integer(kv.second, (long long)it->lo, (long long)it->hi, file, where));
    } else if (const auto* d = std::get_if<double PlacementOptions::*>(&it->member)) {
      o.*(*d) = ranged(kv.second, it->lo, it->hi, file, where);
    } else {
      try {
        o.*std::get<bool PlacementOptions::*>(it->member) = kv.second.as<bool>();
      } catch (const YAML::Exception&) {
        throw Error(file, where, "expected true or false");
      }
    }
  }
}

ObjectiveTerm read_term(const YAML::Node& n, const std::string& file, std::size_t index) {
  const std::string where = "objective[" + std::to_string(index) + "]";
  if (!n.IsMap() || !n["term"]) throw Error(file, where, "expected {term: clearance|depth|distance|upright, ...}");
  require_known_keys(n, {"term", "weight", "direction", "target", "axis"}, file, where);
  ObjectiveTerm t;
  const auto name = n["term"].as<std::string>();
  const auto kind = runtime::parse_objective_kind(name);
  if (!kind) throw Error(file, where + ".term", "unknown term '" + name + "' (clearance, depth, distance, upright)");
  t.kind = *kind;
  if (n["weight"]) t.weight = ranged(n["weight"], -1e6, 1e6, file, where + ".weight");
  const char* key = t.kind == ObjectiveTerm::Kind::Depth      ? "direction"
                    : t.kind == ObjectiveTerm::Kind::Distance ? "target"
                    : t.kind == ObjectiveTerm::Kind::Upright  ? "axis"
                                                              : nullptr;
  if (key) {
    if (!n[key]) throw Error(file, where, std::string("term '") + name + "' needs '" + key + "' [x, y, z]");
    t.vector = vec3(n[key], file, where + "." + key);
    if (t.kind != ObjectiveTerm::Kind::Distance && !(t.vector.norm() > 1e-9))
      throw Error(file, where + "." + key, "must be a non-zero vector");
    if (t.vector.cwiseAbs().maxCoeff() > kMaxGeometryExtent)
      throw Error(file, where + "." + key, "a coordinate beyond " + std::to_string(int(kMaxGeometryExtent)) + " m");
  }
  for (const char* other : {"direction", "target", "axis"})
    if (n[other] && (!key || std::string(other) != key))
      throw Error(file, where + "." + other, "does not belong to term '" + name + "'");
  return t;
}
// pusher: {arm: BASE:TIP, tcp: [x, y, z, qx, qy, qz, qw], standoff, step, plan_time, plan_iterations}
runtime::PusherSpec read_pusher(const YAML::Node& n, const std::string& file) {
  if (!n.IsMap() || !n["arm"])
    throw Error(file, "pusher", "expected {arm: BASE_LINK:TIP_LINK, tcp: [x, y, z, qx, qy, qz, qw]}");
  require_known_keys(n, {"arm", "tcp", "standoff", "step", "plan_time", "plan_iterations"}, file, "pusher");
  runtime::PusherSpec p;
  const auto arm = n["arm"].as<std::string>();
  const auto colon = arm.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == arm.size() ||
      arm.find(':', colon + 1) != std::string::npos)
    throw Error(file, "pusher.arm", "expected BASE_LINK:TIP_LINK, got '" + arm + "'");
  p.base = arm.substr(0, colon);
  p.tip = arm.substr(colon + 1);
  if (n["tcp"]) {
    const auto v = numbers(n["tcp"], 7, file, "pusher.tcp");
    p.tcp = formats::pose_from_xyz_quaternion(std::span<const double, 7>(v.data(), 7), file, "pusher.tcp");
  }
  if (n["standoff"]) p.standoff = ranged(n["standoff"], 1e-3, 0.5, file, "pusher.standoff");
  if (n["step"]) p.step = ranged(n["step"], 1e-4, 0.05, file, "pusher.step");
  if (n["plan_time"]) p.plan_time = ranged(n["plan_time"], 1e-3, 60, file, "pusher.plan_time");
  if (n["plan_iterations"])
    p.plan_iterations = int(integer(n["plan_iterations"], 1, 1000000, file, "pusher.plan_iterations"));
  return p;
}
}  // namespace

std::filesystem::path resolve_artifact_path(const std::string& text, const std::filesystem::path& root,
                                            bool allow_outside, const std::string& file, const std::string& element) {
  namespace fs = std::filesystem;
  if (text.empty()) throw Error(file, element, "empty path");
  const fs::path p = text;
  const fs::path joined = p.is_absolute() ? p : (root.empty() ? fs::path(".") : root) / p;
  if (allow_outside) return joined;
  // Compare real locations: `..` and symbolic links may not lead a query out of its folder.
  std::error_code ec;
  const fs::path real_root = fs::weakly_canonical(root.empty() ? fs::path(".") : root, ec);
  const fs::path real = fs::weakly_canonical(joined, ec);
  const auto rel = real.lexically_relative(real_root);
  if (ec || rel.empty() || *rel.begin() == "..")
    throw Error(file, element,
                "'" + text + "' resolves to " + real.string() + ", outside the artifact folder " + real_root.string() +
                    " (pass --allow-outside to permit it)");
  return joined;
}

PlacementQueryFile read_placement_query(const std::filesystem::path& path, const std::filesystem::path& artifact_dir,
                                        bool allow_outside) {
  const std::string file = path.string();
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap()) throw Error(file, "", "expected a map (robot, object, environment, start, initial_grasp, ...)");
  require_known_keys(root,
                     {"robot", "object", "environment", "start", "initial_grasp", "volume", "objective", "time_limit",
                      "seed", "variant", "options", "retreat_configuration", "pusher"},
                     file, "");
  PlacementQueryFile f;
  f.path = path;
  f.query.source = file;
  const auto dir = artifact_dir.empty() ? path.parent_path() : artifact_dir;
  try {
    for (auto [key, dst] :
         {std::pair{"robot", &f.robot}, std::pair{"object", &f.object}, std::pair{"environment", &f.environment}}) {
      if (!root[key]) throw Error(file, key, "missing (path of the artifact, relative to the query file)");
      *dst = resolve_artifact_path(root[key].as<std::string>(), dir, allow_outside, file, key);
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
    require_known_keys(g, {"pose", "opening"}, file, "initial_grasp");
    const auto p = numbers(g["pose"], 7, file, "initial_grasp.pose");
    f.query.g0 = formats::pose_from_xyz_quaternion(std::span<const double, 7>(p.data(), 7), file, "initial_grasp.pose");
    if (g["opening"]) f.query.g0_opening = ranged(g["opening"], 1e-4, 1, file, "initial_grasp.opening");
    if (root["volume"]) {
      const auto v = numbers(root["volume"], 6, file, "volume");
      if (v[0] > v[3] || v[1] > v[4] || v[2] > v[5]) throw Error(file, "volume", "min exceeds max");
      for (double x : v)
        if (std::abs(x) > kMaxGeometryExtent)
          throw Error(file, "volume", "a coordinate beyond " + std::to_string(int(kMaxGeometryExtent)) + " m");
      f.query.volume = Eigen::AlignedBox3d(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]));
    }
    if (root["objective"]) {
      const YAML::Node o = root["objective"];
      if (!o.IsSequence() || o.size() == 0) throw Error(file, "objective", "expected a non-empty list of terms");
      f.query.objective.clear();
      for (std::size_t i = 0; i < o.size(); ++i) f.query.objective.push_back(read_term(o[i], file, i));
    }
    if (root["time_limit"]) f.time_limit = ranged(root["time_limit"], 0, kMaxTimeLimit, file, "time_limit");
    if (root["seed"]) f.query.seed = root["seed"].as<std::uint64_t>();
    if (root["variant"]) {
      const auto name = root["variant"].as<std::string>();
      const auto v = runtime::parse_variant(name);
      if (!v) throw Error(file, "variant", "unknown variant '" + name + "' (full, random-grasp, no-regrasp)");
      f.query.variant = *v;
    }
    if (root["options"]) read_options(root["options"], f.query.options, file);
    if (const YAML::Node r = root["retreat_configuration"]) {
      if (!r.IsSequence() || r.size() == 0)
        throw Error(file, "retreat_configuration", "expected a list of the arm's joint values");
      Eigen::VectorXd q(Eigen::Index(r.size()));
      for (std::size_t i = 0; i < r.size(); ++i)
        q[Eigen::Index(i)] = real(r[i], file, "retreat_configuration[" + std::to_string(i) + "]");
      f.query.retreat_configuration = q;
    }
    if (const YAML::Node n = root["pusher"]) f.query.pusher = read_pusher(n, file);
  } catch (const YAML::Exception& e) {
    throw Error(file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1),
                std::string("malformed query: ") + e.msg);
  }
  return f;
}

std::map<std::string, double> world_joint_values(const PlacementQueryFile& f, const RobotModel& robot) {
  std::map<std::string, double> out;
  if (f.start_named.empty()) return out;
  const runtime::Kinematics chain(robot, robot.arm_base, robot.arm_tip);
  for (const auto& [name, value] : f.start_named) {
    const int j = robot.joint_index(name);
    if (j < 0) throw Error(f.path.string(), "start." + name, "no joint of that name in robot '" + robot.name + "'");
    if (chain.chain_slot(j) < 0) out[name] = value;
  }
  return out;
}

Eigen::VectorXd resolve_start(const PlacementQueryFile& f, const runtime::Kinematics& kin) {
  const std::string file = f.path.string();
  Eigen::VectorXd q(kin.dof());
  if (!f.start_list.empty() || f.start_named.empty()) {
    if (int(f.start_list.size()) != kin.dof())
      throw Error(file, "start",
                  "has " + std::to_string(f.start_list.size()) + " values, the arm has " + std::to_string(kin.dof()) +
                      " joints");
    for (int i = 0; i < kin.dof(); ++i) q[i] = f.start_list[std::size_t(i)];
  } else {
    for (int i = 0; i < kin.dof(); ++i) {
      const auto& name = kin.joint_names()[std::size_t(i)];
      auto it = f.start_named.find(name);
      if (it == f.start_named.end()) throw Error(file, "start", "no value for joint '" + name + "'");
      q[i] = it->second;
    }
    // Every name must mean something: a joint outside the chain is set in the world, never
    // silently left where the robot artifact has it.
    const auto& m = kin.model();
    for (const auto& [name, value] : f.start_named) {
      const int j = m.joint_index(name);
      if (j < 0) throw Error(file, "start." + name, "no joint of that name in robot '" + m.name + "'");
      if (kin.chain_slot(j) < 0 && !(std::abs(kin.joint_value(j, q) - value) <= 1e-12))
        throw Error(file, "start." + name,
                    "is outside the planning chain and the world was built without it (PlacementWorld's joint_values, "
                    "tools::world_joint_values)");
    }
  }
  if (!q.allFinite()) throw Error(file, "start", "not finite (NaN or infinity)");
  if (!kin.within_limits(q, 1e-6)) throw Error(file, "start", "outside the arm's joint limits");
  return q;
}

}  // namespace dmgplace::tools
