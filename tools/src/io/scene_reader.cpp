// read_urdf_scene and read_mesh_scene; the YAML reader lives in planning_scene_yaml.cpp.
#include "dmgplace/tools/io/scene_reader.hpp"

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

Scene read_urdf_scene(const std::filesystem::path& urdf, const UrdfOptions& options) {
  const std::string file = urdf.string();
  const RobotModel model = read_urdf(urdf, options);
  // Joints come parent-first (read_urdf's order), so one pass places every link.
  std::vector<Eigen::Isometry3d> world(model.links.size(), Eigen::Isometry3d::Identity());
  for (const Joint& j : model.joints) {
    const double q = j.mimic >= 0 ? j.mimic_offset : 0.0;  // every free joint sits at 0
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (j.type == JointType::Revolute || j.type == JointType::Continuous)
      motion.linear() = Eigen::AngleAxisd(q, j.axis).toRotationMatrix();
    else if (j.type == JointType::Prismatic) motion.translation() = q * j.axis;
    if (j.type != JointType::Fixed && j.type != JointType::Continuous && (q < j.lower || q > j.upper))
      throw Error(file, "joint '" + j.name + "'",
                  "a scene needs fixed joints; this movable joint cannot sit at " + std::to_string(q) + " (limits [" +
                      std::to_string(j.lower) + ", " + std::to_string(j.upper) + "])");
    world[std::size_t(j.child)] = world[std::size_t(j.parent)] * j.origin * motion;
  }
  Scene scene;
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    if (model.links[i].collision.empty()) continue;
    SceneObject obj;
    obj.name = model.links[i].name;
    for (Shape s : model.links[i].collision) {
      s.origin = world[i] * s.origin;
      obj.shapes.push_back(std::move(s));
    }
    scene.objects.push_back(std::move(obj));
  }
  if (scene.objects.empty()) throw Error(file, "", "no link has collision geometry");
  return scene;
}

Scene read_mesh_scene(const std::filesystem::path& mesh, const MeshReadOptions& options) {
  Shape s;
  s.type = ShapeType::Mesh;
  s.mesh = read_mesh(mesh, options);
  s.size = options.scale * options.axis_scale;
  SceneObject obj;
  obj.name = mesh.stem().string();
  obj.shapes.push_back(std::move(s));
  Scene scene;
  scene.objects.push_back(std::move(obj));
  return scene;
}

}  // namespace dmgplace::tools
