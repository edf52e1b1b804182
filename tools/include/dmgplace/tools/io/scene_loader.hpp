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
  // Pose of the scene file's frame in the world (the robot base frame): a camera pose for a scan,
  // a placement offset for a URDF/YAML/mesh scene (MotionBenchMaker's base_offset, for one).
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
};

// .yaml/.yml: read_planning_scene_yaml; .urdf: read_urdf_scene; .pcd: read_scan_scene;
// .stl/.obj/.ply/.dae/.off: read_mesh_scene (case-insensitive). Anything else: dmgplace::Error.
// Every object and point is then expressed in the world through `frame`.
Scene load_scene(const std::filesystem::path& path, const SceneLoadOptions& options = {});

}  // namespace dmgplace::tools
