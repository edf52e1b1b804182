#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>
#include "dmgplace/formats/pose_input.hpp"

#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/tools/io/input_log.hpp"
#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/robot/bake_robot.hpp"

namespace dmgplace::cli {

int run_bake_robot(const BakeRobotArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  tools::InputLog log;  // every file read below goes into the header
  auto colon = a.arm.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == a.arm.size())
    throw Error("--arm", "", "expected BASE_LINK:TIP_LINK, got '" + a.arm + "'");
  tools::RobotBakeOptions o;
  o.urdf = a.urdf;
  o.srdf = a.srdf;
  for (const auto& p : a.package_paths) o.package_paths.emplace_back(p);
  o.arm_base = a.arm.substr(0, colon);
  o.arm_tip = a.arm.substr(colon + 1);
  o.spheres.max_radius = a.sphere_max_radius;
  o.spheres.sample_spacing = a.sphere_spacing;
  o.spheres.max_excess = a.sphere_max_excess;
  o.spheres.max_spheres = a.sphere_count;
  o.self_tables.enabled = a.self_table_step > 0;
  o.self_tables.threads = a.threads;
  if (o.self_tables.enabled) o.self_tables.step = a.self_table_step;
  if (a.tcp) {
    o.tcp = formats::pose_from_xyz_quaternion(*a.tcp, "--tcp", "");
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
    if (used != item.size() - eq - 1 || !std::isfinite(value)) throw Error("--fixed-joints", item, "expected name=value (a finite number)");
    o.fixed_joints.emplace_back(item.substr(0, eq), value);
  }
  if (!a.write_srdf.empty() && !a.srdf.empty())
    throw Error("--write-srdf", "", "writes the pairs computed without an SRDF; --srdf " + a.srdf + " was given");
  o.allowed.samples = a.collision_samples;
  tools::AllowedCollisions decided;
  formats::RobotArtifact robot = tools::bake_robot(o, &decided);
  if (a.srdf.empty()) {
    // Say what was decided (stderr: stdout may carry --json).
    std::cerr << "no --srdf: " << decided.disabled.size() << " of " << decided.checked_pairs << " link pairs may touch ("
              << decided.count(tools::DisableReason::Adjacent) << " adjacent, " << decided.count(tools::DisableReason::Default)
              << " touching in the default pose, " << decided.count(tools::DisableReason::Always) << " always and "
              << decided.count(tools::DisableReason::Never) << " never colliding in " << decided.samples
              << " random configurations)";
    if (!a.write_srdf.empty()) {
      formats::write_file_atomically(a.write_srdf, tools::srdf_text(robot.model, decided.disabled));
      std::cerr << "; written to " << a.write_srdf << " for review (pass it back with --srdf)";
    } else {
      std::cerr << "; --write-srdf FILE writes them for review";
    }
    std::cerr << "\n";
  }
  std::vector<std::filesystem::path> inputs{a.urdf};
  if (!a.srdf.empty()) inputs.emplace_back(a.srdf);
  nlohmann::json params = {{"urdf", a.urdf},
                           {"srdf", a.srdf},
                           {"arm", a.arm},
                           {"package_paths", a.package_paths},
                           {"sphere_max_radius", a.sphere_max_radius},
                           {"sphere_spacing", a.sphere_spacing},
                           {"sphere_max_excess", a.sphere_max_excess},
                           {"sphere_count", a.sphere_count},
                           {"self_table_step", a.self_table_step},
                           {"collision_samples", a.srdf.empty() ? a.collision_samples : 0},
                           {"fixed_joints", a.fixed_joints}};
  if (a.tcp) params["tcp"] = *a.tcp;
  robot.header = make_header(params, inputs, log.files());
  formats::save_robot(std::move(robot), a.out);
  report_written(a.out, a.json, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

}  // namespace dmgplace::cli
