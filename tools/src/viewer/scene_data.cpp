#include "dmgplace/tools/viewer/scene_data.hpp"

#include <cstdint>
#include <nlohmann/json.hpp>

#include "dmgplace/tools/geometry/tessellate.hpp"
#include "dmgplace/tools/viewer/base64.hpp"

namespace dmgplace::tools::viewer {
namespace {
using nlohmann::json;

constexpr Eigen::Index kMaxScanPoints = 300000;  // keeps pages of big scans openable

json mesh_json(const TriMesh& m) {
  std::vector<float> p;
  std::vector<std::uint32_t> i;
  for (Eigen::Index r = 0; r < m.vertices.rows(); ++r)
    for (int c = 0; c < 3; ++c) p.push_back(float(m.vertices(r, c)));
  for (Eigen::Index r = 0; r < m.triangles.rows(); ++r)
    for (int c = 0; c < 3; ++c) i.push_back(std::uint32_t(m.triangles(r, c)));
  return {{"p", base64(p)}, {"i", base64(i)}};
}

json pose_json(const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.rotation());
  return {t.translation().x(), t.translation().y(), t.translation().z(), q.x(), q.y(), q.z(), q.w()};
}

json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

json points_json(const std::vector<Eigen::Vector3d>& pts) {
  json out = json::array();
  for (const auto& p : pts) out.push_back(vec_json(p));
  return out;
}

// Mask cells as flat quads a millimetre above the support, runs along x merged into one quad.
TriMesh region_mesh(const formats::PlacementRegion& g) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  const double z = g.height + 0.001;
  for (int j = 0; j < g.depth; ++j)
    for (int i = 0; i < g.width;) {
      if (!g.mask[std::size_t(i + g.width * j)]) {
        ++i;
        continue;
      }
      const int i0 = i;
      while (i < g.width && g.mask[std::size_t(i + g.width * j)]) ++i;
      const double x0 = g.origin.x() + g.resolution * i0, x1 = g.origin.x() + g.resolution * i;
      const double y0 = g.origin.y() + g.resolution * j, y1 = y0 + g.resolution;
      const int b = int(v.size());
      v.insert(v.end(), {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
      f.insert(f.end(), {{b, b + 1, b + 2}, {b, b + 2, b + 3}});
    }
  TriMesh m;
  m.vertices.resize(Eigen::Index(v.size()), 3);
  m.triangles.resize(Eigen::Index(f.size()), 3);
  for (std::size_t k = 0; k < v.size(); ++k) m.vertices.row(Eigen::Index(k)) = v[k].transpose();
  for (std::size_t k = 0; k < f.size(); ++k) m.triangles.row(Eigen::Index(k)) = f[k].transpose();
  return m;
}

json environment_json(const formats::EnvironmentArtifact& env) {
  json objects = json::array();
  for (const auto& o : env.scene.objects) {
    TriMesh m;
    for (const auto& s : o.shapes) append_mesh(m, tessellate(s));
    if (!m.empty()) objects.push_back({{"name", o.name}, {"mesh", mesh_json(m)}});
  }
  std::vector<float> pts;
  const Eigen::Index n = env.scene.points.rows(), stride = n / kMaxScanPoints + 1;
  for (Eigen::Index r = 0; r < n; r += stride)
    for (int c = 0; c < 3; ++c) pts.push_back(float(env.scene.points(r, c)));
  return {{"objects", objects}, {"points", base64(pts)}};
}

json robot_json(const formats::RobotArtifact& robot, const ArmMotion& motion) {
  json names = json::array(), meshes = json::array();
  for (int l : motion.links) {
    TriMesh m;
    for (const auto& s : robot.model.links[std::size_t(l)].collision) append_mesh(m, tessellate(s));
    names.push_back(robot.model.links[std::size_t(l)].name);
    meshes.push_back(mesh_json(m));
  }
  return {{"names", names}, {"meshes", meshes}};
}

json in_hand_json(const ViewResult& r) {
  json steps = json::array();
  for (const auto& s : r.in_hand) {
    json x = {{"type", s.type}, {"finger1", points_json(s.finger1)}, {"finger2", points_json(s.finger2)}};
    if (s.type == "push") {
      x["distance"] = s.distance;
      x["direction"] = vec_json(s.direction);
    } else {
      x["angle"] = s.angle;
      x["axis"] = vec_json(s.axis);
      x["pivot"] = vec_json(s.pivot);
    }
    steps.push_back(x);
  }
  return steps;
}
}  // namespace

std::string scene_data_json(const ViewResult& r, const ArmMotion& motion, const formats::RobotArtifact& robot,
                            const formats::ObjectArtifact& object, const formats::EnvironmentArtifact& env) {
  json j;
  j["title"] = r.query_file.empty() ? r.file.string() : std::filesystem::path(r.query_file).filename().string();
  j["result"] = r.file.string();
  j["variant"] = r.variant;
  j["solved"] = r.solved;
  j["reason"] = r.reason;
  j["seconds"] = r.seconds;
  j["steps"] = r.path.size() + r.retreat.size();
  j["path_waypoints"] = r.path.size();
  const Eigen::AlignedBox3d vol = r.volume ? *r.volume : env.volume;
  j["volume"] = {vol.min().x(), vol.min().y(), vol.min().z(), vol.max().x(), vol.max().y(), vol.max().z()};
  j["env"] = environment_json(env);
  j["regions"] = json::array();
  for (std::size_t k = 0; k < env.regions.size(); ++k)
    j["regions"].push_back({{"height", env.regions[k].height}, {"mesh", mesh_json(region_mesh(env.regions[k]))}});
  j["robot"] = robot_json(robot, motion);
  j["object"] = {{"mesh", mesh_json(object.mesh)}, {"initial", pose_json(motion.object_initial)}};
  j["motion"] = {
      {"frames", motion.frames},        {"links", base64(motion.link_poses)},  {"object", base64(motion.object_poses)},
      {"times", motion.frame_times},    {"waypoints", motion.waypoint_frames}, {"pushes", motion.push_frames},
      {"retreat", motion.retreat_frame}};
  if (r.solved) {
    j["best"] = {{"objective", r.objective},    {"time", r.time},
                 {"region", r.region},          {"pose", pose_json(r.pose)},
                 {"grasp", pose_json(r.grasp)}, {"opening", r.opening}};
    j["in_hand"] = in_hand_json(r);
  }
  j["improvements"] = json::array();
  for (const auto& i : r.improvements) j["improvements"].push_back({i.time, i.objective});
  // "</" would end the <script> element the text sits in; "<\/" is the same JSON string.
  std::string text = j.dump();
  for (std::size_t p = text.find("</"); p != std::string::npos; p = text.find("</", p + 3)) text.insert(p + 1, "\\");
  return text;
}

}  // namespace dmgplace::tools::viewer
