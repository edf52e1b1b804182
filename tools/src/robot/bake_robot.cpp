#include "dmgplace/tools/robot/bake_robot.hpp"

#include "dmgplace/tools/io/urdf_reader.hpp"

namespace dmgplace::tools {

formats::RobotArtifact bake_robot(const RobotBakeOptions& o) {
  UrdfOptions urdf;
  urdf.package_paths = o.package_paths;
  formats::RobotArtifact robot;
  robot.model = read_urdf(o.urdf, urdf);
  if (!o.srdf.empty()) apply_srdf(robot.model, o.srdf);
  set_arm_chain(robot.model, o.arm_base, o.arm_tip, o.urdf.string());
  for (std::size_t l = 0; l < robot.model.links.size(); ++l)
    for (const auto& s : cover_with_spheres(robot.model.links[l].collision, o.spheres))
      robot.spheres.push_back({int(l), s.center, s.radius});
  return robot;
}

}  // namespace dmgplace::tools
