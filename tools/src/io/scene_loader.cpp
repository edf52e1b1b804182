#include "dmgplace/tools/io/scene_loader.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/shape_table.hpp"
#include "dmgplace/tools/io/pcd_reader.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"

namespace dmgplace::tools {

namespace {
Scene in_world(Scene scene, const Eigen::Isometry3d& frame) {
  for (auto& object : scene.objects)
    for (auto& shape : object.shapes) shape.origin = frame * shape.origin;
  return scene;
}

// What every baked environment must satisfy (the artifact's own check), applied to the scene as
// read, so a 1e300 m box or 100k objects are refused before any grid or BVH is built.
Scene checked(Scene scene, const std::filesystem::path& path) {
  constexpr std::size_t kMaxObjects = 10000, kMaxShapes = 100000;
  std::size_t shapes = 0;
  for (const auto& object : scene.objects) shapes += object.shapes.size();
  if (scene.objects.size() > kMaxObjects || shapes > kMaxShapes)
    throw Error(path.string(), "",
                std::to_string(scene.objects.size()) + " objects with " + std::to_string(shapes) +
                    " shapes: more than this build handles (" + std::to_string(kMaxObjects) + " objects, " +
                    std::to_string(kMaxShapes) + " shapes)");
  for (const auto& object : scene.objects) {
    std::vector<formats::OwnedShape> own;
    for (const auto& sh : object.shapes) own.push_back({0, sh});
    const auto problems = formats::check_shapes(own, 1, "object '" + object.name + "' shape");
    if (!problems.empty()) throw Error(path.string(), "", problems.front());
  }
  if (scene.points.size() > 0 && (!scene.points.allFinite() || scene.points.cwiseAbs().maxCoeff() > kMaxGeometryExtent))
    throw Error(path.string(), "points",
                "a point is not finite or beyond " + std::to_string(int(kMaxGeometryExtent)) + " m");
  return scene;
}

Scene load_any(const std::filesystem::path& path, const SceneLoadOptions& options) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".yaml" || ext == ".yml")
    return in_world(read_planning_scene_yaml(path, options.urdf.package_paths), options.frame);
  if (ext == ".urdf") return in_world(read_urdf_scene(path, options.urdf), options.frame);
  if (ext == ".pcd") return read_scan_scene(path, options.frame);
  if (ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".dae" || ext == ".off")
    return in_world(read_mesh_scene(path, options.mesh), options.frame);
  throw Error(
      path.string(), "",
      "unknown scene file type '" + ext + "' (expected .yaml, .yml, .urdf, .pcd, .stl, .obj, .ply, .dae, .off)");
}
}  // namespace

Scene load_scene(const std::filesystem::path& path, const SceneLoadOptions& options) {
  return checked(load_any(path, options), path);
}

}  // namespace dmgplace::tools
