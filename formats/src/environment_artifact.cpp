#include "dmgplace/formats/environment_artifact.hpp"

#include <algorithm>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/shape_table.hpp"
#include "format_util.hpp"

namespace dmgplace::formats {
namespace {

// A grid as `<group>/values` (nz, ny, nx) f32 and `<group>/grid` (6) f64:
// origin x y z, resolution, band, signed (1/0). An empty grid is stored with shape (0, 0, 0).
void write_grid(H5Writer& w, const std::string& group, const FieldGrid& g, bool is_signed) {
  double spec[6] = {g.origin.x(), g.origin.y(), g.origin.z(), g.resolution, g.band, is_signed ? 1.0 : 0.0};
  w.write(group + "/grid", std::span<const double>(spec), {6});
  std::vector<std::size_t> dims = {std::size_t(g.dims[2]), std::size_t(g.dims[1]), std::size_t(g.dims[0])};
  if (g.values.empty()) dims = {0, 0, 0};
  // Read whole on every load: contiguous and uncompressed, so loading is one copy, no inflate.
  w.write_contiguous(group + "/values", std::span<const float>(g.values), dims);
}

FieldGrid read_grid(const H5Reader& r, const std::string& group, bool* is_signed) {
  auto spec = r.read_f64(group + "/grid", {6});
  auto v = r.read_f32(group + "/values", {-1, -1, -1});
  FieldGrid g;
  g.origin = Eigen::Vector3d(spec.data[0], spec.data[1], spec.data[2]);
  g.resolution = spec.data[3];
  g.band = spec.data[4];
  if (is_signed) *is_signed = spec.data[5] != 0;
  if (v.data.empty()) return g;
  constexpr std::size_t kMaxAxis = 1u << 20;
  for (std::size_t a = 0; a < 3; ++a)
    if (v.dims[a] < 2 || v.dims[a] > kMaxAxis)
      throw Error(r.file(), group + "/values", "each axis needs 2 to 2^20 samples");
  g.dims = {int(v.dims[2]), int(v.dims[1]), int(v.dims[0])};
  g.values = std::move(v.data);
  return g;
}

// Regions as flat tables: scalars (N,5) f64 height, area, x0, y0, resolution; index (N,4) i64
// width, depth, first cell, surface; mask (M) u8 and free_height (M) f32 concatenated.
void write_regions(H5Writer& w, const std::vector<PlacementRegion>& regions) {
  std::vector<double> scalars;
  std::vector<std::int64_t> index;
  std::vector<std::uint8_t> mask;
  std::vector<float> free_height;
  for (const auto& r : regions) {
    scalars.insert(scalars.end(), {r.height, r.area, r.origin.x(), r.origin.y(), r.resolution});
    index.insert(index.end(), {r.width, r.depth, std::int64_t(mask.size()), r.surface});
    mask.insert(mask.end(), r.mask.begin(), r.mask.end());
    free_height.insert(free_height.end(), r.free_height.begin(), r.free_height.end());
  }
  w.write("regions/scalars", std::span<const double>(scalars), {regions.size(), 5});
  w.write("regions/index", std::span<const std::int64_t>(index), {regions.size(), 4});
  w.write("regions/mask", std::span<const std::uint8_t>(mask), {mask.size()});
  w.write("regions/free_height", std::span<const float>(free_height), {free_height.size()});
}

std::vector<PlacementRegion> read_regions(const H5Reader& r) {
  auto scalars = r.read_f64("regions/scalars", {-1, 5});
  auto index = r.read_i64("regions/index", {(long)scalars.rows(), 4});
  auto mask = r.read_u8("regions/mask", {-1});
  auto free_height = r.read_f32("regions/free_height", {(long)mask.rows()});
  std::vector<PlacementRegion> out(scalars.rows());
  for (std::size_t i = 0; i < out.size(); ++i) {
    auto& g = out[i];
    g.height = scalars(i, 0);
    g.area = scalars(i, 1);
    g.origin = Eigen::Vector2d(scalars(i, 2), scalars(i, 3));
    g.resolution = scalars(i, 4);
    const std::int64_t w = index(i, 0), d = index(i, 1), first = index(i, 2);
    const std::string where = "regions/index row " + std::to_string(i);
    if (w < 1 || d < 1 || w > (1 << 20) || d > (1 << 20))
      throw Error(r.file(), where, "width and depth must be 1 to 2^20 cells");
    if (first < 0 || std::size_t(first) > mask.data.size() ||
        std::size_t(w * d) > mask.data.size() - std::size_t(first))
      throw Error(r.file(), where, "cell range outside regions/mask");
    g.width = int(w);
    g.depth = int(d);
    g.surface = int(std::clamp<std::int64_t>(index(i, 3), -1, 1 << 30));
    g.mask.assign(mask.data.begin() + first, mask.data.begin() + first + w * d);
    g.free_height.assign(free_height.data.begin() + first, free_height.data.begin() + first + w * d);
  }
  return out;
}

}  // namespace

std::size_t PlacementRegion::cell_count() const {
  return std::size_t(std::count_if(mask.begin(), mask.end(), [](std::uint8_t m) { return m != 0; }));
}

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
  for (const FieldGrid* g : {&a.sdf, &a.clearance})
    if (!g->empty() && g->values.size() != g->size())
      throw Error(path.string(), g == &a.sdf ? "fields/sdf" : "fields/clearance",
                  "values do not match the grid dimensions");
  write_grid(w, "fields/sdf", a.sdf, a.sdf_signed);
  write_grid(w, "fields/clearance", a.clearance, false);
  for (std::size_t i = 0; i < a.regions.size(); ++i) {
    const auto& r = a.regions[i];
    const std::size_t cells = std::size_t(std::max(r.width, 0)) * std::size_t(std::max(r.depth, 0));
    if (r.mask.size() != cells || r.free_height.size() != cells)
      throw Error(path.string(), "regions[" + std::to_string(i) + "]", "mask and free_height need width x depth cells");
  }
  write_regions(w, a.regions);
  w.commit();
}

EnvironmentArtifact load_environment(const std::filesystem::path& path) {
  EnvironmentArtifact a = read_environment_unchecked(path);
  detail::require_sound(path.string(), check_environment(a));
  return a;
}

EnvironmentArtifact read_environment_unchecked(const std::filesystem::path& path) {
  H5Reader r(path);
  r.require_schema(kEnvironmentSchema, kEnvironmentSchemaVersion);
  EnvironmentArtifact a;
  a.header = r.header();
  a.header.source_file = r.file();
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
  a.sdf = read_grid(r, "fields/sdf", &a.sdf_signed);
  a.clearance = read_grid(r, "fields/clearance", nullptr);
  a.regions = read_regions(r);
  return a;
}

Summary summarize_environment(const EnvironmentArtifact& a) {
  std::size_t shapes = 0, triangles = 0;
  for (const auto& o : a.scene.objects)
    for (const auto& s : o.shapes) {
      ++shapes;
      triangles += std::size_t(s.mesh.triangles.rows());
    }
  auto grid_text = [](const FieldGrid& g) {
    if (g.empty()) return std::string("none");
    return std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]) + " at " +
           detail::fmt(g.resolution) + " m, band " + detail::fmt(g.band) + " m";
  };
  double area = 0;
  for (const auto& r : a.regions) area += r.area;
  Summary s;
  s.emplace_back("objects", std::to_string(a.scene.objects.size()));
  s.emplace_back("shapes", std::to_string(shapes));
  s.emplace_back("mesh_triangles", std::to_string(triangles));
  s.emplace_back("scan_points", std::to_string(a.scene.points.rows()));
  s.emplace_back("volume_min", detail::fmt(Eigen::Vector3d(a.volume.min())));
  s.emplace_back("volume_max", detail::fmt(Eigen::Vector3d(a.volume.max())));
  s.emplace_back("sdf", grid_text(a.sdf) + (a.sdf.empty() ? "" : a.sdf_signed ? ", signed" : ", unsigned"));
  s.emplace_back("clearance", grid_text(a.clearance));
  s.emplace_back("regions", std::to_string(a.regions.size()));
  s.emplace_back("region_area_m2", detail::fmt(area));
  return s;
}

}  // namespace dmgplace::formats
