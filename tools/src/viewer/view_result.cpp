#include "dmgplace/tools/viewer/view_result.hpp"
#include "dmgplace/formats/pose_input.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools::viewer {
namespace {
using nlohmann::json;

// Typed access that reports the JSON pointer of a missing or mistyped element.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  const json& at(const json& j, const std::string& ptr) const {
    const json::json_pointer p(ptr);
    if (!j.contains(p)) fail(ptr, "missing");
    return j.at(p);
  }
  double number(const json& j, const std::string& ptr) const {
    const json& v = at(j, ptr);
    if (!v.is_number()) fail(ptr, "not a number");
    return v.get<double>();
  }
  std::string text(const json& j, const std::string& ptr) const {
    const json& v = at(j, ptr);
    if (!v.is_string()) fail(ptr, "not a string");
    return v.get<std::string>();
  }
  std::vector<double> numbers(const json& j, const std::string& ptr, std::size_t n = 0) const {
    const json& v = at(j, ptr);
    if (!v.is_array()) fail(ptr, "not a list");
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); ++i) out.push_back(number(v, "/" + std::to_string(i)));
    if (n && out.size() != n)
      fail(ptr, "expected " + std::to_string(n) + " numbers, got " + std::to_string(out.size()));
    return out;
  }
  Eigen::Vector3d vec3(const json& j, const std::string& ptr) const {
    const auto v = numbers(j, ptr, 3);
    return {v[0], v[1], v[2]};
  }
  // [x, y, z, qx, qy, qz, qw]
  Eigen::Isometry3d pose(const json& j, const std::string& ptr) const {
    const auto v = numbers(j, ptr, 7);
    return formats::pose_from_xyz_quaternion(std::span<const double, 7>(v.data(), 7), file_, ptr);
  }
  std::vector<Eigen::VectorXd> joint_path(const json& j, const std::string& ptr, std::size_t dof) const {
    const json& v = at(j, ptr);
    if (!v.is_array()) fail(ptr, "not a list");
    std::vector<Eigen::VectorXd> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto q = numbers(j, ptr + "/" + std::to_string(i), dof);
      out.push_back(Eigen::Map<const Eigen::VectorXd>(q.data(), Eigen::Index(q.size())));
    }
    return out;
  }
  std::vector<Eigen::Vector3d> points(const json& j, const std::string& ptr) const {
    std::vector<Eigen::Vector3d> out;
    if (!j.contains(json::json_pointer(ptr))) return out;
    for (std::size_t i = 0; i < at(j, ptr).size(); ++i) out.push_back(vec3(j, ptr + "/" + std::to_string(i)));
    return out;
  }
  // {time, positions}: times from 0, not decreasing; one row of `dof` positions per time.
  runtime::Trajectory trajectory(const json& j, const std::string& ptr, std::size_t dof) const {
    runtime::Trajectory t;
    t.time = numbers(j, ptr + "/time");
    for (const auto& q : joint_path(j, ptr + "/positions", dof))
      t.positions.emplace_back(q.data(), q.data() + q.size());
    if (t.positions.size() != t.time.size()) fail(ptr, "time and positions differ in length");
    for (std::size_t i = 0; i < t.time.size(); ++i)
      if (!std::isfinite(t.time[i]) || t.time[i] < (i ? t.time[i - 1] : 0.0))
        fail(ptr + "/time/" + std::to_string(i), "not finite, or before the previous time (or below 0)");
    return t;
  }
  [[noreturn]] void fail(const std::string& ptr, const std::string& why) const { throw Error(file_, ptr, why); }

 private:
  std::string file_;
};

json parse_json(const std::filesystem::path& path, const std::string& missing) {
  std::ifstream in(path);
  if (!in) throw Error(path.string(), "", "cannot open" + missing);
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw Error(path.string(), "", std::string("not valid JSON: ") + e.what());
  }
}

InHandStep read_step(const Reader& r, const json& j, const std::string& at) {
  InHandStep s;
  s.type = r.text(j, at + "/type");
  if (s.type == "push") {
    s.distance = r.number(j, at + "/distance");
    s.direction = r.vec3(j, at + "/push_direction");
  } else if (s.type == "rotate") {
    s.angle = r.number(j, at + "/angle");
    s.axis = r.vec3(j, at + "/axis");
    s.pivot = r.vec3(j, at + "/pivot");
  } else {
    r.fail(at + "/type", "unknown in-hand action '" + s.type + "' (push, rotate)");
  }
  s.finger1 = r.points(j, at + "/finger1_path");
  s.finger2 = r.points(j, at + "/finger2_path");
  return s;
}
}  // namespace

ViewResult read_view_result(const std::filesystem::path& result_dir, const std::filesystem::path& artifacts) {
  ViewResult v;
  v.file = result_dir / "result.json";
  const std::string file = v.file.string();
  const json j = parse_json(v.file, " (write it with `dmgplace place QUERY --out DIR`)");
  const Reader r(file);
  const auto artifact = [&](const char* key) {
    const std::filesystem::path p = r.text(j, std::string("/query/") + key);
    return artifacts.empty() ? p : artifacts / p.filename();
  };
  v.robot = artifact("robot");
  v.object = artifact("object");
  v.environment = artifact("environment");
  v.query_file = j.value(json::json_pointer("/query/file"), std::string());
  v.variant = j.value(json::json_pointer("/query/variant"), std::string());
  for (std::size_t i = 0; i < r.at(j, "/joint_names").size(); ++i)
    v.joint_names.push_back(r.text(j, "/joint_names/" + std::to_string(i)));
  const auto start = r.numbers(j, "/query/start", v.joint_names.size());
  v.start = Eigen::Map<const Eigen::VectorXd>(start.data(), Eigen::Index(start.size()));
  v.initial_grasp = r.pose(j, "/query/initial_grasp");
  if (j["query"].contains("joint_values"))
    for (const auto& [name, value] : r.at(j, "/query/joint_values").items())
      v.joint_values[name] = r.number(j, "/query/joint_values/" + name);
  if (j["query"].contains("volume")) {
    const auto b = r.numbers(j, "/query/volume", 6);
    v.volume = Eigen::AlignedBox3d(Eigen::Vector3d(b[0], b[1], b[2]), Eigen::Vector3d(b[3], b[4], b[5]));
  }
  const json& solved = r.at(j, "/solved");
  if (!solved.is_boolean()) r.fail("/solved", "not true or false");
  v.solved = solved.get<bool>();
  v.reason = j.value("reason", std::string());
  v.seconds = j.value("seconds", 0.0);
  if (j.contains("improvements"))
    for (std::size_t i = 0; i < r.at(j, "/improvements").size(); ++i) {
      const std::string at = "/improvements/" + std::to_string(i);
      v.improvements.push_back({r.number(j, at + "/time"), r.number(j, at + "/objective")});
    }
  if (!v.solved) return v;
  v.time = r.number(j, "/best/time");
  v.objective = r.number(j, "/best/objective");
  v.region = j["best"].value("region", -1);
  v.pose = r.pose(j, "/best/pose");
  v.grasp = r.pose(j, "/best/grasp/pose");
  v.opening = r.number(j, "/best/grasp/opening");
  if (j["best"].contains("release_opening")) v.release_opening = r.number(j, "/best/release_opening");
  for (std::size_t i = 0; i < r.at(j, "/best/in_hand").size(); ++i)
    v.in_hand.push_back(read_step(r, j, "/best/in_hand/" + std::to_string(i)));
  v.path = r.joint_path(j, "/best/path", v.joint_names.size());
  v.retreat = r.joint_path(j, "/best/retreat", v.joint_names.size());
  if (v.path.empty()) r.fail("/best/path", "empty: a solution starts at the start configuration");
  if (j["best"].contains("pushes")) {
    const std::string arm = r.text(j, "/query/pusher/arm");
    v.pusher_tip = arm.substr(arm.find(':') + 1);
    for (std::size_t i = 0; i < r.at(j, "/pusher_joint_names").size(); ++i)
      v.pusher_joint_names.push_back(r.text(j, "/pusher_joint_names/" + std::to_string(i)));
    for (std::size_t i = 0; i < r.at(j, "/best/pushes").size(); ++i) {
      const std::string at = "/best/pushes/" + std::to_string(i);
      ViewResult::Push p;
      p.path = r.joint_path(j, at + "/path", v.pusher_joint_names.size());
      p.begin = int(r.number(j, at + "/push_begin"));
      p.end = int(r.number(j, at + "/push_end"));
      if (j.contains(json::json_pointer(at + "/trajectory")))
        p.timing = r.trajectory(j, at + "/trajectory", v.pusher_joint_names.size());
      if (p.path.empty() || p.begin < 0 || p.end < p.begin || p.end >= int(p.path.size()))
        r.fail(at, "push_begin/push_end not within the path");
      p.object_before = r.pose(j, at + "/object_before");
      p.object_after = r.pose(j, at + "/object_after");
      v.pushes.push_back(std::move(p));
    }
  }
  // The grasping arm's timed trajectories: older results have no trajectory.json.
  const std::filesystem::path timing = result_dir / "trajectory.json";
  if (std::filesystem::exists(timing)) {
    const json t = parse_json(timing, "");
    const Reader tr(timing.string());
    v.path_timing = tr.trajectory(t, "/approach", v.joint_names.size());
    v.retreat_timing = tr.trajectory(t, "/retreat", v.joint_names.size());
  }
  return v;
}

}  // namespace dmgplace::tools::viewer
