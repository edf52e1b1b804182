#include "dmgplace/tools/io/scene_loader.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/pcd_reader.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"

namespace dmgplace::tools {

Scene load_scene(const std::filesystem::path& path, const SceneLoadOptions& options) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".yaml" || ext == ".yml") return read_planning_scene_yaml(path, options.urdf.package_paths);
  if (ext == ".urdf") return read_urdf_scene(path, options.urdf);
  if (ext == ".pcd") return read_scan_scene(path, options.scan_frame);
  if (ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".dae" || ext == ".off")
    return read_mesh_scene(path, options.mesh);
  throw Error(
      path.string(), "",
      "unknown scene file type '" + ext + "' (expected .yaml, .yml, .urdf, .pcd, .stl, .obj, .ply, .dae, .off)");
}

}  // namespace dmgplace::tools
