#pragma once
// Inputs for runtime tests, made by the offline tools and handed over as the formats types the
// runtime loads. Runtime test files include this header and no tools header: the tools themselves
// are tested in tools_tests.
#include <filesystem>
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::test {

// A robot description as bake-robot reads it: URDF, optional SRDF, package:// roots.
RobotModel read_robot_model(const std::filesystem::path& urdf, const std::filesystem::path& srdf = {},
                            const std::vector<std::filesystem::path>& package_paths = {});
// The bake's sphere cover of every link with collision geometry.
std::vector<formats::LinkSphere> robot_spheres(const RobotModel& model);
// The bake's self-distance tables for the chain of `kin`.
std::vector<formats::SelfDistanceTable> self_distance_tables(const runtime::Kinematics& kin,
                                                             const std::vector<formats::LinkSphere>& spheres);
// The table bake's defaults: nodes with a distance below `exact_below` are within `tolerance` of
// exact; others may hold the Lipschitz bound of a coarse cell `coarse_stride` nodes wide.
struct SelfTableDefaults {
  double exact_below;
  double coarse_stride;
  double tolerance;
};
SelfTableDefaults self_table_defaults();

// A scene file as bake-env reads it (PlanningScene YAML, URDF, PCD).
Scene read_scene(const std::filesystem::path& path);
// Bakes `env` (scene and volume set) with bake-env's defaults.
void bake_environment(formats::EnvironmentArtifact& env);

// The built-in procedural meshes.
TriMesh box_mesh(const Eigen::Vector3d& extents);
TriMesh bottle_mesh();
TriMesh eraser_mesh();
// bake-object's placement faces and DMG (default gripper and options).
formats::PlacementFaces placement_faces(const TriMesh& mesh, const Eigen::Vector3d& com);
formats::Dmg dmg(const TriMesh& mesh);

}  // namespace dmgplace::test
