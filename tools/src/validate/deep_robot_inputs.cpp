// validate --deep --check-inputs for ROBOT.h5: the joint limits against the URDF (and MoveIt
// joint_limits.yaml) its header names, where they are found. A stored range may only be narrower,
// a stored velocity or acceleration only lower: wider ones let plans leave what the robot allows.
#include <algorithm>
#include <cmath>

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
  uo.skip_collision = true;
  RobotModel ref = read_urdf(urdf, uo);
  if (!limits.empty()) apply_joint_limits(ref, limits);
  WorstOf w;
  int samples = 0;
  for (const auto& j : a.model.joints) {
    if (j.type == JointType::Fixed) continue;
    const int r = ref.joint_index(j.name);
    ++samples;
    if (r < 0) {
      w.add(std::numeric_limits<double>::infinity(), "joint '" + j.name + "' is not in " + urdf.string());
      continue;
    }
    const Joint& rj = ref.joints[std::size_t(r)];
    w.add(excess(j, rj), "joint '" + j.name + "': stored [" + fmt(j.lower) + ", " + fmt(j.upper) + "] velocity " + fmt(j.velocity) +
                             " acceleration " + fmt(j.acceleration) + ", inputs [" + fmt(rj.lower) + ", " + fmt(rj.upper) +
                             "] velocity " + fmt(rj.velocity) + " acceleration " + fmt(rj.acceleration));
  }
  report.checks.push_back({"joint limits within the URDF's" + std::string(limits.empty() ? "" : " and joint_limits.yaml's"),
                           "joints/values", samples, w.worst, kLimitTolerance, "rad, m or per s", w.sample});
}

}  // namespace dmgplace::tools::detail
