#include "dmgplace/formats/object_artifact.hpp"

#include <algorithm>
#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "format_util.hpp"

namespace dmgplace::formats {
namespace {

constexpr std::size_t kFaceReals = 9;      // normal(3) rotation xyzw(4) margin height
constexpr std::size_t kGripperReals = 12;  // see GripperModel, in declaration order
constexpr std::size_t kNodeInts = 5;       // patch facet opposite_patch first_angle angle_count
constexpr std::size_t kNodeReals = 15;     // position normal zero_axis opposite_point opposite_normal

void put(std::vector<double>& v, const Eigen::Vector3d& x) { v.insert(v.end(), {x.x(), x.y(), x.z()}); }
Eigen::Vector3d get3(const Array<double>& a, std::size_t r, std::size_t c) {
  return {a(r, c), a(r, c + 1), a(r, c + 2)};
}

void write_placement(H5Writer& w, const PlacementFaces& p) {
  std::vector<double> faces, points;
  std::vector<std::int64_t> ranges;
  for (const auto& f : p.faces) {
    put(faces, f.normal);
    faces.insert(faces.end(), {f.rotation.x(), f.rotation.y(), f.rotation.z(), f.rotation.w(), f.margin, f.height});
    ranges.insert(ranges.end(), {std::int64_t(points.size() / 3), std::int64_t(f.polygon.size())});
    for (const auto& q : f.polygon) put(points, q);
  }
  const double settings[2] = {p.merge_angle, p.required_margin};
  w.write("placement/settings", std::span<const double>(settings), {2});
  w.write("placement/faces", std::span<const double>(faces), {p.faces.size(), kFaceReals});
  w.write("placement/polygon_ranges", std::span<const std::int64_t>(ranges), {p.faces.size(), 2});
  w.write("placement/polygon_points", std::span<const double>(points), {points.size() / 3, 3});
}

PlacementFaces read_placement(const H5Reader& r) {
  PlacementFaces p;
  auto s = r.read_f64("placement/settings", {2});
  p.merge_angle = s.data[0];
  p.required_margin = s.data[1];
  auto faces = r.read_f64("placement/faces", {-1, long(kFaceReals)});
  auto ranges = r.read_i64("placement/polygon_ranges", {long(faces.rows()), 2});
  auto points = r.read_f64("placement/polygon_points", {-1, 3});
  for (std::size_t i = 0; i < faces.rows(); ++i) {
    PlacementFace f;
    f.normal = get3(faces, i, 0);
    f.rotation = Eigen::Quaterniond(faces(i, 6), faces(i, 3), faces(i, 4), faces(i, 5));
    f.margin = faces(i, 7);
    f.height = faces(i, 8);
    const std::int64_t first = ranges(i, 0), count = ranges(i, 1);
    if (!detail::range_within(first, count, points.rows()))
      throw Error(r.file(), "placement/polygon_ranges", "face " + std::to_string(i) + " range out of bounds");
    for (std::int64_t k = first; k < first + count; ++k) f.polygon.push_back(get3(points, std::size_t(k), 0));
    p.faces.push_back(std::move(f));
  }
  return p;
}

void write_dmg(H5Writer& w, const Dmg& d) {
  const double settings[4] = {d.angle_step_deg, d.seed_resolution, d.normal_threshold, double(d.patch_count)};
  w.write("dmg/settings", std::span<const double>(settings), {4});
  const GripperModel& g = d.gripper;
  const double grip[kGripperReals] = {g.max_opening,     g.finger_length,   g.finger_width,    g.finger_thickness,
                                      g.tip_offset,      g.palm_size.x(),   g.palm_size.y(),   g.palm_size.z(),
                                      g.palm_center.x(), g.palm_center.y(), g.palm_center.z(), g.contact_tolerance};
  w.write("dmg/gripper", std::span<const double>(grip), {kGripperReals});
  std::vector<double> facets;
  for (std::size_t i = 0; i < d.facet_normals.size(); ++i) {
    put(facets, d.facet_normals[i]);
    put(facets, d.facet_zero_axes.at(i));
  }
  w.write("dmg/facets", std::span<const double>(facets), {d.facet_normals.size(), 6});
  std::vector<std::int32_t> ints;
  std::vector<double> reals;
  for (const auto& n : d.nodes) {
    ints.insert(ints.end(), {n.patch, n.facet, n.opposite_patch, n.first_angle, n.angle_count});
    for (const auto* v : {&n.position, &n.normal, &n.zero_axis, &n.opposite_point, &n.opposite_normal}) put(reals, *v);
  }
  w.write("dmg/node_indices", std::span<const std::int32_t>(ints), {d.nodes.size(), kNodeInts});
  w.write("dmg/node_geometry", std::span<const double>(reals), {d.nodes.size(), kNodeReals});
  std::vector<std::int32_t> edges;
  for (auto [a, b] : d.edges) edges.insert(edges.end(), {a, b});
  w.write("dmg/edges", std::span<const std::int32_t>(edges), {d.edges.size(), 2});
}

Dmg read_dmg(const H5Reader& r) {
  Dmg d;
  auto s = r.read_f64("dmg/settings", {4});
  d.angle_step_deg = s.data[0];
  d.seed_resolution = s.data[1];
  d.normal_threshold = s.data[2];
  d.patch_count = detail::checked_int(s.data[3], 0, 1 << 30, r.file(), "dmg/settings patch count");
  auto g = r.read_f64("dmg/gripper", {long(kGripperReals)}).data;
  d.gripper = {g[0], g[1], g[2], g[3], g[4], {g[5], g[6], g[7]}, {g[8], g[9], g[10]}, g[11]};
  auto facets = r.read_f64("dmg/facets", {-1, 6});
  for (std::size_t i = 0; i < facets.rows(); ++i) {
    d.facet_normals.push_back(get3(facets, i, 0));
    d.facet_zero_axes.push_back(get3(facets, i, 3));
  }
  auto ints = r.read_i32("dmg/node_indices", {-1, long(kNodeInts)});
  auto reals = r.read_f64("dmg/node_geometry", {long(ints.rows()), long(kNodeReals)});
  for (std::size_t i = 0; i < ints.rows(); ++i) {
    DmgNode n;
    n.patch = ints(i, 0);
    n.facet = ints(i, 1);
    n.opposite_patch = ints(i, 2);
    n.first_angle = ints(i, 3);
    n.angle_count = ints(i, 4);
    n.position = get3(reals, i, 0);
    n.normal = get3(reals, i, 3);
    n.zero_axis = get3(reals, i, 6);
    n.opposite_point = get3(reals, i, 9);
    n.opposite_normal = get3(reals, i, 12);
    d.nodes.push_back(n);
  }
  auto edges = r.read_i32("dmg/edges", {-1, 2});
  for (std::size_t i = 0; i < edges.rows(); ++i) d.edges.push_back({edges(i, 0), edges(i, 1)});
  return d;
}

void write_grasp_graph(H5Writer& w, const GraspGraphTable& t) {
  const std::size_t n = t.state_node.size();
  std::vector<std::int32_t> states;
  for (std::size_t i = 0; i < n; ++i) states.insert(states.end(), {t.state_node[i], t.state_angle[i]});
  w.write("grasp_graph/states", std::span<const std::int32_t>(states), {n, 2});
  w.write("grasp_graph/offsets", std::span<const std::int32_t>(t.offsets), {t.offsets.size()});
  w.write("grasp_graph/targets", std::span<const std::int32_t>(t.targets), {t.targets.size()});
  w.write("grasp_graph/costs", std::span<const double>(t.costs), {t.costs.size()});
  std::vector<std::uint8_t> moves(t.moves.size());
  std::transform(t.moves.begin(), t.moves.end(), moves.begin(), [](GraspMoveKind m) { return std::uint8_t(m); });
  w.write("grasp_graph/moves", std::span<const std::uint8_t>(moves), {moves.size()});
  w.write("grasp_graph/tcp", std::span<const double>(t.tcp), {n, 7});
  w.write("grasp_graph/opening", std::span<const double>(t.opening), {n});
  const double settings[1] = {t.rotation_weight};
  w.write("grasp_graph/settings", std::span<const double>(settings), {1});
  w.attribute("grasp_graph", "schema_version", std::to_string(kGraspGraphSchemaVersion));
}

GraspGraphTable read_grasp_graph(const H5Reader& r) {
  const auto version = r.attribute("grasp_graph", "schema_version");
  if (version != std::to_string(kGraspGraphSchemaVersion))
    throw Error(r.file(), "grasp_graph",
                "schema version is " + version.value_or("missing") + ", this build reads " +
                    std::to_string(kGraspGraphSchemaVersion) + " (re-bake the object)");
  GraspGraphTable t;
  t.rotation_weight = r.read_f64("grasp_graph/settings", {1}).data[0];
  auto states = r.read_i32("grasp_graph/states", {-1, 2});
  for (std::size_t i = 0; i < states.rows(); ++i) {
    t.state_node.push_back(states(i, 0));
    t.state_angle.push_back(states(i, 1));
  }
  t.offsets = r.read_i32("grasp_graph/offsets", {long(states.rows()) + 1}).data;
  t.targets = r.read_i32("grasp_graph/targets", {-1}).data;
  t.costs = r.read_f64("grasp_graph/costs", {long(t.targets.size())}).data;
  for (auto m : r.read_u8("grasp_graph/moves", {long(t.targets.size())}).data) t.moves.push_back(GraspMoveKind(m));
  t.tcp = r.read_f64("grasp_graph/tcp", {long(states.rows()), 7}).data;
  t.opening = r.read_f64("grasp_graph/opening", {long(states.rows())}).data;
  // Indices the runtime follows without a check of its own: refuse them here, as the DMG's.
  const long n = long(states.rows());
  for (std::size_t s = 0; s < t.offsets.size(); ++s)
    if (t.offsets[s] < 0 || std::size_t(t.offsets[s]) > t.targets.size() || (s > 0 && t.offsets[s] < t.offsets[s - 1]))
      throw Error(r.file(), "grasp_graph/offsets",
                  "not a non-decreasing index into the edges at state " + std::to_string(s));
  if (!t.offsets.empty() && std::size_t(t.offsets.back()) != t.targets.size())
    throw Error(r.file(), "grasp_graph/offsets", "the last offset is not the edge count");
  for (auto u : t.targets)
    if (u < 0 || u >= n)
      throw Error(r.file(), "grasp_graph/targets", "state index " + std::to_string(u) + " out of range");
  return t;
}

}  // namespace

int Dmg::angle_count() const { return angle_step_deg > 0 ? int(std::lround(360.0 / angle_step_deg)) : 0; }

void save_object(ObjectArtifact a, const std::filesystem::path& path) {
  a.header.schema = kObjectSchema;
  a.header.schema_version = kObjectSchemaVersion;
  H5Writer w(path, a.header);
  detail::write_mesh(w, "mesh", a.mesh);
  const auto& m = a.mass;
  double scalars[2] = {m.volume, m.mass};
  w.write("mass/volume_mass", std::span<const double>(scalars), {2});
  w.write("mass/com", std::span<const double>(m.com.data(), 3), {3});
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> inertia = m.inertia;
  w.write("mass/inertia", std::span<const double>(inertia.data(), 9), {3, 3});
  w.attribute("mass", "com_overridden", m.com_overridden ? "true" : "false");
  write_placement(w, a.placement);
  write_dmg(w, a.dmg);
  if (a.grasp_graph.state_node.empty() && !a.dmg.nodes.empty()) a.grasp_graph = build_grasp_graph_table(a.dmg);
  write_grasp_graph(w, a.grasp_graph);
  w.commit();
}

ObjectArtifact load_object(const std::filesystem::path& path) {
  ObjectArtifact a = read_object_unchecked(path);
  detail::require_sound(path.string(), check_object(a));
  return a;
}

ObjectArtifact read_object_unchecked(const std::filesystem::path& path) {
  H5Reader r(path);
  r.require_schema(kObjectSchema, kObjectSchemaVersion);
  ObjectArtifact a;
  a.header = r.header();
  a.header.source_file = r.file();
  a.mesh = detail::read_mesh(r, "mesh");
  auto vm = r.read_f64("mass/volume_mass", {2});
  a.mass.volume = vm.data[0];
  a.mass.mass = vm.data[1];
  auto com = r.read_f64("mass/com", {3});
  a.mass.com = Eigen::Vector3d(com.data[0], com.data[1], com.data[2]);
  auto in = r.read_f64("mass/inertia", {3, 3});
  a.mass.inertia = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(in.data.data());
  a.mass.com_overridden = r.attribute("mass", "com_overridden").value_or("false") == "true";
  a.placement = read_placement(r);
  a.dmg = read_dmg(r);
  a.grasp_graph = read_grasp_graph(r);
  return a;
}

Summary summarize_object(const ObjectArtifact& a) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < a.mesh.vertices.rows(); ++i) box.extend(a.mesh.vertices.row(i).transpose());
  Summary s;
  s.emplace_back("vertices", std::to_string(a.mesh.vertices.rows()));
  s.emplace_back("triangles", std::to_string(a.mesh.triangles.rows()));
  s.emplace_back("bounds_min", detail::fmt(Eigen::Vector3d(box.min())));
  s.emplace_back("bounds_max", detail::fmt(Eigen::Vector3d(box.max())));
  s.emplace_back("volume_m3", detail::fmt(a.mass.volume));
  s.emplace_back("mass_kg", detail::fmt(a.mass.mass));
  s.emplace_back("com", detail::fmt(a.mass.com));
  s.emplace_back("placement_faces", std::to_string(a.placement.faces.size()));
  s.emplace_back("dmg_patches", std::to_string(a.dmg.patch_count));
  s.emplace_back("dmg_facets", std::to_string(a.dmg.facet_normals.size()));
  s.emplace_back("dmg_nodes", std::to_string(a.dmg.nodes.size()));
  s.emplace_back("dmg_edges", std::to_string(a.dmg.edges.size()));
  s.emplace_back("grasp_states", std::to_string(a.grasp_graph.size()));
  s.emplace_back("grasp_edges", std::to_string(a.grasp_graph.edge_count()));
  return s;
}

}  // namespace dmgplace::formats
