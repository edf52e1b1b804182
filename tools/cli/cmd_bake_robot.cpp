#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>
#include <cstdio>
#include "dmgplace/formats/pose_input.hpp"

#include "cli_log.hpp"
#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/tools/io/input_log.hpp"
#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/robot/bake_robot.hpp"

namespace dmgplace::cli {

OptionTable BakeRobotArgs::options() {
  return {
      {"--srdf", "srdf", &srdf, 0, 0, "", "SRDF with disabled collision pairs (without one they are computed)"},
      {"--joint-limits", "joint_limits", &joint_limits, 0, 0, "",
       "MoveIt joint_limits.yaml: velocity and acceleration limits for timed trajectories (default: URDF velocities, 1 "
       "rad/s^2)"},
      {"--fixed-joints", "fixed_joints", &fixed_joints, 0, 0, "",
       "name=value,... joints outside the chain (another arm, a torso) frozen there (rad or m); default: their URDF "
       "zero"},
      {"--write-srdf", "", &write_srdf, 0, 0, "",
       "Without --srdf: write the computed disabled pairs as an SRDF to review"},
      {"--collision-samples", "collision_samples", &allowed.samples, 1, 1e6, "",
       "Without --srdf: random configurations that decide always/never-colliding pairs"},
      {"--package-path", "package_paths", &package_paths, 0, 0, "", "Where package:// resources are found"},
      {"--arm", "arm", &arm, 0, 0, "", "Planning chain BASE_LINK:TIP_LINK"},
      {"--sphere-max-radius", "sphere_max_radius", &spheres.max_radius, 1e-3, 10, "m",
       "Sphere model: split spheres larger than this"},
      {"--sphere-spacing", "sphere_spacing", &spheres.sample_spacing, 1e-4, 1, "m",
       "Sphere model: sample spacing on and inside the links"},
      {"--sphere-count", "sphere_count", &spheres.max_spheres, 1, 10000, "", "Sphere model: most spheres per link"},
      {"--sphere-max-excess", "sphere_max_excess", &spheres.max_excess, 1e-4, 1, "m",
       "Sphere model: how far a radius may exceed half its cluster's median extent"},
      {"--self-table-step", "self_table_step", &self_table_step, 0, 1, "rad",
       "Self-distance table grid step; 0: no tables"},
      {"--self-table-stride", "self_table_stride", &self_tables.coarse_stride, 1, 64, "",
       "Self-distance tables: exact distances every Nth node first, others bounded from them when far from contact"},
      {"--self-table-exact-below", "self_table_exact_below", &self_tables.exact_below, 0, 10, "m",
       "Self-distance tables: nodes bounded below this are computed exactly"},
      {"--self-table-tolerance", "self_table_tolerance", &self_tables.tolerance, 0, 0.01, "m",
       "Self-distance tables: a node near contact may store a proven bound this close below its exact distance "
       "(0: FCL's exact distance at every such node)"},
      {"--threads", "", &threads, 0, 256, "", "Worker threads; 0: every CPU the process may use"},
      {"--out", "", &out, 0, 0, "", "Output artifact"},
      {"--json", "", &json, 0, 0, "",
       "Print JSON: the file written, seconds taken, and the artifact's summary (as inspect --json)"},
  };
}

int run_bake_robot(const BakeRobotArgs& a_in) {
  BakeRobotArgs a = a_in;
  const auto t0 = std::chrono::steady_clock::now();
  tools::InputLog log;  // every file read below goes into the header
  nlohmann::ordered_json params = option_parameters(a.options());
  params["urdf"] = a.urdf;
  if (!a.srdf.empty()) params["collision_samples"] = 0;  // not used with an SRDF
  auto colon = a.arm.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == a.arm.size())
    throw Error("--arm", "", "expected BASE_LINK:TIP_LINK, got '" + a.arm + "'");
  tools::RobotBakeOptions o;
  o.urdf = a.urdf;
  o.srdf = a.srdf;
  o.joint_limits = a.joint_limits;
  for (const auto& p : a.package_paths) o.package_paths.emplace_back(p);
  o.arm_base = a.arm.substr(0, colon);
  o.arm_tip = a.arm.substr(colon + 1);
  o.spheres = a.spheres;
  o.self_tables = a.self_tables;
  o.self_tables.enabled = a.self_table_step > 0;
  o.self_tables.threads = a.threads;
  if (o.self_tables.enabled) o.self_tables.step = a.self_table_step;
  o.allowed = a.allowed;
  o.allowed.threads = a.threads;
  if (!a.tcp_text.empty()) {
    const auto t = parse_numbers<7>(a.tcp_text, "--tcp");
    o.tcp = formats::pose_from_xyz_quaternion(t, "--tcp", "");
    params["tcp"] = t;
  }
  // --fixed-joints name=value,name=value
  std::stringstream list(a.fixed_joints);
  for (std::string item; std::getline(list, item, ',');) {
    const auto eq = item.find('=');
    if (item.empty()) continue;
    std::size_t used = 0;
    double value = 0;
    try {
      if (eq == std::string::npos || eq == 0) throw std::invalid_argument("no name=value");
      value = std::stod(item.substr(eq + 1), &used);
    } catch (const std::exception&) {
      throw Error("--fixed-joints", item, "expected name=value (a number in rad or m)");
    }
    if (used != item.size() - eq - 1 || !std::isfinite(value))
      throw Error("--fixed-joints", item, "expected name=value (a finite number)");
    o.fixed_joints.emplace_back(item.substr(0, eq), value);
  }
  if (!a.write_srdf.empty() && !a.srdf.empty())
    throw Error("--write-srdf", "", "writes the pairs computed without an SRDF; --srdf " + a.srdf + " was given");
  o.self_tables.progress = progress_line();  // on a terminal: the tables take seconds to minutes
  tools::AllowedCollisions decided;
  std::vector<std::string> notes;
  formats::RobotArtifact robot = tools::bake_robot(o, &decided, &notes);
  for (const auto& n : notes) log_info(a.joint_limits + ": " + n);
  if (a.srdf.empty()) {
    // Say what was decided (stderr: stdout may carry --json).
    std::ostringstream m;
    m << "no --srdf: " << decided.disabled.size() << " of " << decided.checked_pairs << " link pairs may touch ("
      << decided.count(tools::DisableReason::Adjacent) << " adjacent, " << decided.count(tools::DisableReason::Default)
      << " touching in the default pose, " << decided.count(tools::DisableReason::Always) << " always and "
      << decided.count(tools::DisableReason::Never) << " never colliding in " << decided.samples
      << " random configurations)";
    if (!a.write_srdf.empty()) {
      formats::write_file_atomically(a.write_srdf, tools::srdf_text(robot.model, decided.disabled));
      m << "; written to " << a.write_srdf << " for review (pass it back with --srdf)";
    } else {
      m << "; --write-srdf FILE writes them for review";
    }
    log_info(m.str());
  }
  std::vector<std::filesystem::path> inputs{a.urdf};
  if (!a.srdf.empty()) inputs.emplace_back(a.srdf);
  if (!a.joint_limits.empty()) inputs.emplace_back(a.joint_limits);
  robot.header = make_header(params, inputs, log.files());
  formats::save_robot(std::move(robot), a.out);
  report_written(a.out, a.json, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

}  // namespace dmgplace::cli
