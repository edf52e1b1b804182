// validate --deep --check-inputs for ROBOT.h5: the joint limits against the URDF (and MoveIt
// joint_limits.yaml) its header names, where they are found. A stored range may only be narrower,
// a stored velocity or acceleration only lower: wider ones let plans leave what the robot allows.
// And every link's collision geometry against the URDF's, its meshes read again.
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/stale_inputs.hpp"
#include "dmgplace/tools/io/joint_limits_reader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/validate/deep_checks.hpp"

namespace dmgplace::tools::detail {
namespace {

constexpr double kLimitTolerance = 1e-9;

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// How far the stored joint exceeds the reference: range beyond it (rad or m), and velocity and
// acceleration above it (absolute units).
double excess(const Joint& stored, const Joint& ref) {
  double e = std::max(ref.lower - stored.lower, stored.upper - ref.upper);
  if (ref.velocity > 0) e = std::max(e, stored.velocity - ref.velocity);
  if (ref.acceleration > 0) e = std::max(e, stored.acceleration - ref.acceleration);
  if (stored.type != ref.type) e = std::numeric_limits<double>::infinity();
  return e;
}

// How far link geometry `stored` is from `ref` (the URDF's): the largest vertex or size or origin
// difference (m), infinite where the shapes differ in count or kind.
double geometry_gap(const std::vector<Shape>& stored, const std::vector<Shape>& ref) {
  if (stored.size() != ref.size()) return std::numeric_limits<double>::infinity();
  double gap = 0;
  for (std::size_t k = 0; k < stored.size(); ++k) {
    const Shape &s = stored[k], &r = ref[k];
    if (s.type != r.type || s.mesh.vertices.rows() != r.mesh.vertices.rows() || s.mesh.triangles != r.mesh.triangles)
      return std::numeric_limits<double>::infinity();
    gap = std::max(
        {gap, (s.size - r.size).cwiseAbs().maxCoeff(), (s.origin.matrix() - r.origin.matrix()).cwiseAbs().maxCoeff()});
    if (s.mesh.vertices.rows() > 0) gap = std::max(gap, (s.mesh.vertices - r.mesh.vertices).cwiseAbs().maxCoeff());
  }
  return gap;
}

DeepCheck links_against(const formats::RobotArtifact& a, const RobotModel& ref, const std::string& urdf) {
  WorstOf w;
  int samples = 0;
  for (const auto& l : a.model.links) {
    const int r = ref.link_index(l.name);
    if (r < 0) continue;  // added by the bake (a TCP frame)
    ++samples;
    w.add(geometry_gap(l.collision, ref.links[std::size_t(r)].collision), [&] {
      return "link '" + l.name + "': " + std::to_string(l.collision.size()) + " shapes stored, " +
             std::to_string(ref.links[std::size_t(r)].collision.size()) + " in " + urdf;
    });
  }
  return {"link collision geometry equal to the URDF's (meshes read again)",
          "links/collision",
          samples,
          w.worst,
          1e-9,
          "m",
          w.sample};
}

}  // namespace

void robot_against_inputs(const formats::RobotArtifact& a, const std::filesystem::path& file, DeepReport& report) {
  std::filesystem::path urdf, limits;
  for (const auto& s : formats::check_inputs(file)) {
    if (s.at.empty()) {
      report.notes.push_back("input " + s.path + " not found: not compared");
      continue;
    }
    if (ends_with(s.path, ".urdf")) urdf = s.at;
    else if (ends_with(s.path, ".yaml") || ends_with(s.path, ".yml")) limits = s.at;
  }
  if (urdf.empty()) {
    report.notes.push_back("no URDF among the inputs at hand: joint limits not compared");
    return;
  }
  UrdfOptions uo;
  const auto params = nlohmann::json::parse(a.header.parameters_json, nullptr, false);
  if (!params.is_discarded() && params.contains("package_paths") && params["package_paths"].is_array())
    for (const auto& p : params["package_paths"])
      if (p.is_string()) uo.package_paths.emplace_back(p.get<std::string>());
  RobotModel ref;
  try {
    ref = read_urdf(urdf, uo);
    report.checks.push_back(links_against(a, ref, urdf.string()));
  } catch (const Error& e) {  // a mesh not at hand (package paths are as the bake was given them)
    report.notes.push_back(std::string("link geometry not compared: ") + e.what());
    uo.skip_collision = true;
    ref = read_urdf(urdf, uo);
  }
  if (!limits.empty()) apply_joint_limits(ref, limits);
  WorstOf w;
  int samples = 0;
  for (const auto& j : a.model.joints) {
    if (j.type == JointType::Fixed) continue;
    const int r = ref.joint_index(j.name);
    ++samples;
    if (r < 0) {
      w.add(std::numeric_limits<double>::infinity(),
            [&] { return "joint '" + j.name + "' is not in " + urdf.string(); });
      continue;
    }
    const Joint& rj = ref.joints[std::size_t(r)];
    w.add(excess(j, rj), [&] {
      return "joint '" + j.name + "': stored [" + fmt(j.lower) + ", " + fmt(j.upper) + "] velocity " + fmt(j.velocity) +
             " acceleration " + fmt(j.acceleration) + ", inputs [" + fmt(rj.lower) + ", " + fmt(rj.upper) +
             "] velocity " + fmt(rj.velocity) + " acceleration " + fmt(rj.acceleration);
    });
  }
  report.checks.push_back(
      {"joint limits within the URDF's" + std::string(limits.empty() ? "" : " and joint_limits.yaml's"),
       "joints/values", samples, w.worst, kLimitTolerance, "rad, m or per s", w.sample});
}

}  // namespace dmgplace::tools::detail
