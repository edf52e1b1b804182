#include "fixtures.hpp"

#include "dmgplace/tools/geometry/procedural_meshes.hpp"
#include "dmgplace/tools/environment/bake_environment.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/object/dmg_builder.hpp"
#include "dmgplace/tools/object/gripper_model.hpp"
#include "dmgplace/tools/object/placement_faces.hpp"
#include "dmgplace/tools/robot/self_distance_tables.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"

namespace dmgplace::test {

RobotModel read_robot_model(const std::filesystem::path& urdf, const std::filesystem::path& srdf,
                            const std::vector<std::filesystem::path>& package_paths) {
  tools::UrdfOptions o;
  o.package_paths = package_paths;
  RobotModel model = tools::read_urdf(urdf, o);
  if (!srdf.empty()) tools::apply_srdf(model, srdf);
  return model;
}

std::vector<formats::LinkSphere> robot_spheres(const RobotModel& model) {
  std::vector<formats::LinkSphere> spheres;
  for (std::size_t l = 0; l < model.links.size(); ++l)
    for (const auto& s : tools::cover_with_spheres(model.links[l].collision))
      spheres.push_back({int(l), s.center, s.radius});
  return spheres;
}

std::vector<formats::SelfDistanceTable> self_distance_tables(const runtime::Kinematics& kin,
                                                             const std::vector<formats::LinkSphere>& spheres) {
  return tools::build_self_distance_tables(kin, spheres);
}

SelfTableDefaults self_table_defaults() {
  const tools::SelfTableOptions o;
  return {o.exact_below, double(o.coarse_stride), o.tolerance};
}

Scene read_scene(const std::filesystem::path& path) { return tools::load_scene(path); }

void bake_environment(formats::EnvironmentArtifact& env) { tools::bake_environment(env, tools::EnvironmentBakeOptions{}); }

TriMesh box_mesh(const Eigen::Vector3d& extents) { return tools::make_box_mesh(extents); }
TriMesh bottle_mesh() { return tools::make_bottle_mesh(); }
TriMesh eraser_mesh() { return tools::make_eraser_mesh(); }

formats::PlacementFaces placement_faces(const TriMesh& mesh, const Eigen::Vector3d& com) {
  return tools::compute_placement_faces(mesh, com, tools::FaceOptions{}, "fixture");
}

formats::Dmg dmg(const TriMesh& mesh) { return tools::build_dmg(mesh, tools::default_gripper(), {}, "fixture"); }

}  // namespace dmgplace::test
