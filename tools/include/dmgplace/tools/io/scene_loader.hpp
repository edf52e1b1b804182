#pragma once
// Loads any supported scene file, choosing the reader by extension.
#include <Eigen/Geometry>
#include <filesystem>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"

namespace dmgplace::tools {

struct SceneLoadOptions {
  UrdfOptions urdf;      // package paths, for package:// in URDF and YAML scenes
  MeshReadOptions mesh;  // for a scene that is one mesh file
  Eigen::Isometry3d scan_frame = Eigen::Isometry3d::Identity();  // pose of a .pcd cloud in the world
};

// .yaml/.yml: read_planning_scene_yaml; .urdf: read_urdf_scene; .pcd: read_scan_scene;
// .stl/.obj/.ply/.dae/.off: read_mesh_scene (case-insensitive). Anything else: dmgplace::Error.
Scene load_scene(const std::filesystem::path& path, const SceneLoadOptions& options = {});

}  // namespace dmgplace::tools
