#include "dmgplace/tools/io/scene_loader.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/pcd_reader.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"

namespace dmgplace::tools {

namespace {
Scene in_world(Scene scene, const Eigen::Isometry3d& frame) {
  for (auto& object : scene.objects)
    for (auto& shape : object.shapes) shape.origin = frame * shape.origin;
  return scene;
}
}  // namespace

Scene load_scene(const std::filesystem::path& path, const SceneLoadOptions& options) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".yaml" || ext == ".yml") return in_world(read_planning_scene_yaml(path, options.urdf.package_paths), options.frame);
  if (ext == ".urdf") return in_world(read_urdf_scene(path, options.urdf), options.frame);
  if (ext == ".pcd") return read_scan_scene(path, options.frame);
  if (ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".dae" || ext == ".off")
    return in_world(read_mesh_scene(path, options.mesh), options.frame);
  throw Error(
      path.string(), "",
      "unknown scene file type '" + ext + "' (expected .yaml, .yml, .urdf, .pcd, .stl, .obj, .ply, .dae, .off)");
}

}  // namespace dmgplace::tools
