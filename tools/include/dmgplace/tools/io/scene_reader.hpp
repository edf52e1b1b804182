#pragma once
// Reads obstacle scenes: MoveIt PlanningScene YAML, a URDF of fixed links, or one mesh file.
// Every object's shapes come out in world coordinates (Shape::origin is the world pose).
#include <filesystem>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"

namespace dmgplace::tools {

// MoveIt PlanningScene YAML: world.collision_objects[] with id, optional pose (prefixes the
// shapes), primitives + primitive_poses (box [x, y, z], cylinder [height, radius], sphere
// [radius]) and meshes + mesh_poses (a `resource` path, relative to the YAML or package://, or
// inline `vertices` + `triangles`). Poses are position [x, y, z] + orientation [x, y, z, w]
// (maps {x: .., ...} work too). Objects whose header.frame_id is a child frame of
// fixed_frame_transforms are moved by that transform; other frames are taken as the world.
// Other keys (robot_state, allowed_collision_matrix, ...) are ignored. Any malformed element is
// a dmgplace::Error naming the object id and the field.
Scene read_planning_scene_yaml(const std::filesystem::path& yaml,
                               const std::vector<std::filesystem::path>& package_paths = {});

// One object per link that has collision shapes, placed by forward kinematics at q = 0.
// A movable joint is accepted only where q = 0 lies within its limits (it is placed there).
Scene read_urdf_scene(const std::filesystem::path& urdf, const UrdfOptions& options = {});

// One object (named after the file stem) holding the mesh at the world origin.
Scene read_mesh_scene(const std::filesystem::path& mesh, const MeshReadOptions& options = {});

}  // namespace dmgplace::tools
