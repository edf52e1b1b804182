#include "dmgplace/formats/environment_artifact.hpp"

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/shape_table.hpp"
#include "format_util.hpp"

namespace dmgplace::formats {

void save_environment(EnvironmentArtifact a, const std::filesystem::path& path) {
  a.header.schema = kEnvironmentSchema;
  a.header.schema_version = kEnvironmentSchemaVersion;
  H5Writer w(path, a.header);
  double v[6] = {a.volume.min().x(), a.volume.min().y(), a.volume.min().z(),
                 a.volume.max().x(), a.volume.max().y(), a.volume.max().z()};
  w.write("volume", std::span<const double>(v), {6});
  std::vector<std::string> names;
  std::vector<OwnedShape> shapes;
  for (std::size_t i = 0; i < a.scene.objects.size(); ++i) {
    names.push_back(a.scene.objects[i].name);
    for (const auto& s : a.scene.objects[i].shapes) shapes.push_back({int(i), s});
  }
  w.write_strings("scene/object_names", names);
  write_shapes(w, "scene/shapes", shapes);
  const auto& pts = a.scene.points;
  w.write("scene/points", std::span<const double>(pts.data(), std::size_t(pts.size())), {std::size_t(pts.rows()), 3});
  w.commit();
}

EnvironmentArtifact load_environment(const std::filesystem::path& path) {
  H5Reader r(path);
  r.require_schema(kEnvironmentSchema, kEnvironmentSchemaVersion);
  EnvironmentArtifact a;
  a.header = r.header();
  auto v = r.read_f64("volume", {6});
  a.volume = Eigen::AlignedBox3d(Eigen::Vector3d(v.data[0], v.data[1], v.data[2]),
                                 Eigen::Vector3d(v.data[3], v.data[4], v.data[5]));
  auto names = r.read_strings("scene/object_names");
  a.scene.objects.resize(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) a.scene.objects[i].name = names[i];
  for (auto& os : read_shapes(r, "scene/shapes")) {
    if (os.owner < 0 || std::size_t(os.owner) >= names.size())
      throw Error(r.file(), "scene/shapes/owner", "object index out of range");
    a.scene.objects[std::size_t(os.owner)].shapes.push_back(std::move(os.shape));
  }
  auto pts = r.read_f64("scene/points", {-1, 3});
  a.scene.points = Eigen::Map<const RowMatrixX3d>(pts.data.data(), Eigen::Index(pts.rows()), 3);
  return a;
}

std::vector<std::string> check_environment(const EnvironmentArtifact& a) {
  std::vector<std::string> p;
  if (!a.volume.min().allFinite() || !a.volume.max().allFinite()) p.push_back("volume: not finite");
  else if ((a.volume.min().array() >= a.volume.max().array()).any()) p.push_back("volume: min must be below max on every axis");
  std::vector<OwnedShape> shapes;
  for (std::size_t i = 0; i < a.scene.objects.size(); ++i)
    for (const auto& s : a.scene.objects[i].shapes) shapes.push_back({int(i), s});
  detail::append(p, check_shapes(shapes, int(a.scene.objects.size()), "scene/shapes"));
  if (!a.scene.points.allFinite()) p.push_back("scene/points: non-finite point");
  if (shapes.empty() && a.scene.points.rows() == 0) p.push_back("scene: no obstacles and no scan points");
  return p;
}

Summary summarize_environment(const EnvironmentArtifact& a) {
  std::size_t shapes = 0, triangles = 0;
  for (const auto& o : a.scene.objects)
    for (const auto& s : o.shapes) {
      ++shapes;
      triangles += std::size_t(s.mesh.triangles.rows());
    }
  Summary s;
  s.emplace_back("objects", std::to_string(a.scene.objects.size()));
  s.emplace_back("shapes", std::to_string(shapes));
  s.emplace_back("mesh_triangles", std::to_string(triangles));
  s.emplace_back("scan_points", std::to_string(a.scene.points.rows()));
  s.emplace_back("volume_min", detail::fmt(Eigen::Vector3d(a.volume.min())));
  s.emplace_back("volume_max", detail::fmt(Eigen::Vector3d(a.volume.max())));
  return s;
}

}  // namespace dmgplace::formats
