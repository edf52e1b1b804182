#include <iostream>

#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"

namespace dmgplace::cli {

int run_bake_robot(const BakeRobotArgs& a) {
  auto colon = a.arm.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == a.arm.size())
    throw Error("--arm", "", "expected BASE_LINK:TIP_LINK, got '" + a.arm + "'");
  tools::UrdfOptions opts;
  for (const auto& p : a.package_paths) opts.package_paths.emplace_back(p);
  formats::RobotArtifact robot;
  robot.model = tools::read_urdf(a.urdf, opts);
  std::vector<std::filesystem::path> inputs{a.urdf};
  if (!a.srdf.empty()) {
    tools::apply_srdf(robot.model, a.srdf);
    inputs.emplace_back(a.srdf);
  }
  tools::set_arm_chain(robot.model, a.arm.substr(0, colon), a.arm.substr(colon + 1), a.urdf);
  tools::SphereCoverOptions cover;
  cover.max_radius = a.sphere_max_radius;
  cover.sample_spacing = a.sphere_spacing;
  for (std::size_t l = 0; l < robot.model.links.size(); ++l)
    for (const auto& s : tools::cover_with_spheres(robot.model.links[l].collision, cover))
      robot.spheres.push_back({int(l), s.center, s.radius});
  nlohmann::json params = {{"urdf", a.urdf},
                           {"srdf", a.srdf},
                           {"arm", a.arm},
                           {"package_paths", a.package_paths},
                           {"sphere_max_radius", a.sphere_max_radius},
                           {"sphere_spacing", a.sphere_spacing}};
  robot.header = make_header(params, inputs);
  formats::save_robot(std::move(robot), a.out);
  report_written(a.out);
  return 0;
}

}  // namespace dmgplace::cli
