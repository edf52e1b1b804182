#include "dmgplace/formats/shape_table.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "dmgplace/formats/error.hpp"
#include "format_util.hpp"
#include "points_above_plane.hpp"

namespace dmgplace::formats {

void pose_to_array(const Eigen::Isometry3d& pose, double* out) {
  Eigen::Quaterniond q(pose.rotation());
  q.normalize();
  out[0] = pose.translation().x();
  out[1] = pose.translation().y();
  out[2] = pose.translation().z();
  out[3] = q.x();
  out[4] = q.y();
  out[5] = q.z();
  out[6] = q.w();
}

Eigen::Isometry3d pose_from_array(const double* in, const std::string& file, const std::string& element) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond q(in[6], in[3], in[4], in[5]);
  // Writers store unit quaternions. A zero one would silently read as the identity (every term of
  // the rotation matrix is a product of two components) and a NaN one as garbage: refuse both.
  if (!(std::abs(q.norm() - 1) <= 1e-6))
    throw Error(file, element, "pose quaternion is not of unit length (zero or corrupt)");
  q.normalize();
  p.linear() = q.toRotationMatrix();
  p.translation() = Eigen::Vector3d(in[0], in[1], in[2]);
  return p;
}

void write_shapes(H5Writer& w, const std::string& g, const std::vector<OwnedShape>& shapes) {
  const std::size_t k = shapes.size();
  std::vector<std::int32_t> type(k), owner(k);
  std::vector<double> size(3 * k), pose(7 * k);
  std::vector<std::int64_t> ranges(4 * k);
  std::vector<double> verts;
  std::vector<std::int32_t> tris, hull;
  std::vector<std::int64_t> hull_ranges(2 * k);
  for (std::size_t i = 0; i < k; ++i) {
    const Shape& s = shapes[i].shape;
    type[i] = int(s.type);
    owner[i] = shapes[i].owner;
    for (int j = 0; j < 3; ++j) size[3 * i + j] = s.size[j];
    pose_to_array(s.origin, &pose[7 * i]);
    ranges[4 * i + 0] = std::int64_t(verts.size() / 3);
    ranges[4 * i + 1] = s.mesh.vertices.rows();
    ranges[4 * i + 2] = std::int64_t(tris.size() / 3);
    ranges[4 * i + 3] = s.mesh.triangles.rows();
    for (Eigen::Index r = 0; r < s.mesh.vertices.rows(); ++r)
      for (int c = 0; c < 3; ++c) verts.push_back(s.mesh.vertices(r, c));
    for (Eigen::Index r = 0; r < s.mesh.triangles.rows(); ++r)
      for (int c = 0; c < 3; ++c) tris.push_back(s.mesh.triangles(r, c));
    hull_ranges[2 * i + 0] = std::int64_t(hull.size() / 3);
    hull_ranges[2 * i + 1] = s.hull.rows();
    for (Eigen::Index r = 0; r < s.hull.rows(); ++r)
      for (int c = 0; c < 3; ++c) hull.push_back(s.hull(r, c));
  }
  w.write(g + "/type", std::span<const std::int32_t>(type), {k});
  w.write(g + "/owner", std::span<const std::int32_t>(owner), {k});
  w.write(g + "/size", std::span<const double>(size), {k, 3});
  w.write(g + "/pose", std::span<const double>(pose), {k, 7});
  w.write(g + "/mesh_ranges", std::span<const std::int64_t>(ranges), {k, 4});
  w.write(g + "/mesh_vertices", std::span<const double>(verts), {verts.size() / 3, 3});
  w.write(g + "/mesh_triangles", std::span<const std::int32_t>(tris), {tris.size() / 3, 3});
  w.write(g + "/hull_ranges", std::span<const std::int64_t>(hull_ranges), {k, 2});
  w.write(g + "/hull_triangles", std::span<const std::int32_t>(hull), {hull.size() / 3, 3});
}

std::vector<OwnedShape> read_shapes(const H5Reader& r, const std::string& g) {
  auto type = r.read_i32(g + "/type", {-1});
  const long k = long(type.rows());
  auto owner = r.read_i32(g + "/owner", {k});
  auto size = r.read_f64(g + "/size", {k, 3});
  auto pose = r.read_f64(g + "/pose", {k, 7});
  auto ranges = r.read_i64(g + "/mesh_ranges", {k, 4});
  auto verts = r.read_f64(g + "/mesh_vertices", {-1, 3});
  auto tris = r.read_i32(g + "/mesh_triangles", {-1, 3});
  // Hulls: optional (environment artifacts before they were written carry none).
  const bool hulls = r.has(g + "/hull_ranges");
  auto hull_ranges = hulls ? r.read_i64(g + "/hull_ranges", {k, 2}) : decltype(r.read_i64("", {})){};
  auto hull = hulls ? r.read_i32(g + "/hull_triangles", {-1, 3}) : decltype(tris){};
  std::vector<OwnedShape> out(static_cast<std::size_t>(k));
  for (long i = 0; i < k; ++i) {
    auto& o = out[std::size_t(i)];
    const std::string el = g + "[" + std::to_string(i) + "]";
    if (type.data[i] < 0 || type.data[i] > 3)
      throw Error(r.file(), el, "unknown shape type " + std::to_string(type.data[i]));
    o.owner = owner.data[i];
    o.shape.type = ShapeType(type.data[i]);
    o.shape.size = Eigen::Vector3d(size(i, 0), size(i, 1), size(i, 2));
    o.shape.origin = pose_from_array(&pose.data[7 * i], r.file(), el + " pose");
    const std::int64_t v0 = ranges(i, 0), vn = ranges(i, 1), t0 = ranges(i, 2), tn = ranges(i, 3);
    if (!detail::range_within(v0, vn, verts.rows()) || !detail::range_within(t0, tn, tris.rows()))
      throw Error(r.file(), el, "mesh range outside the mesh tables");
    o.shape.mesh.vertices.resize(vn, 3);
    o.shape.mesh.triangles.resize(tn, 3);
    for (std::int64_t a = 0; a < vn; ++a)
      for (int c = 0; c < 3; ++c) o.shape.mesh.vertices(a, c) = verts(std::size_t(v0 + a), c);
    for (std::int64_t a = 0; a < tn; ++a)
      for (int c = 0; c < 3; ++c) {
        int idx = tris(std::size_t(t0 + a), c);
        if (idx < 0 || idx >= vn) throw Error(r.file(), el, "mesh triangle index out of range");
        o.shape.mesh.triangles(a, c) = idx;
      }
    if (!hulls) continue;
    const std::int64_t h0 = hull_ranges(i, 0), hn = hull_ranges(i, 1);
    if (!detail::range_within(h0, hn, hull.rows())) throw Error(r.file(), el, "hull range outside the hull table");
    o.shape.hull.resize(hn, 3);
    for (std::int64_t a = 0; a < hn; ++a)  // indices are checked with the rest (hull_problem)
      for (int c = 0; c < 3; ++c) o.shape.hull(a, c) = hull(std::size_t(h0 + a), c);
  }
  return out;
}

std::optional<std::string> hull_problem(const TriMesh& mesh, const RowMatrixX3i& hull) {
  if (hull.rows() < 4) return "convex hull with fewer than 4 triangles";
  if (hull.minCoeff() < 0 || hull.maxCoeff() >= mesh.vertices.rows()) return "convex hull triangle index out of range";
  // A closed surface (each directed edge once, and its reverse once): the runtime takes the hull's
  // vertices from its triangles, so a missing face could drop a vertex that matters.
  std::vector<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < hull.rows(); ++f)
    for (int k = 0; k < 3; ++k) edges.emplace_back(hull(f, k), hull(f, (k + 1) % 3));
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end())
    return "convex hull has a repeated edge (not a closed surface)";
  for (auto [a, b] : edges)
    if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(b, a)))
      return "convex hull is not closed (an edge without its twin)";
  // Every vertex on the inner side of every hull face: the gaps measured against the hull are
  // then lower bounds of the mesh's. The tolerance covers rounding in the planes only.
  const double tol = 1e-9 * std::max(1.0, mesh.vertices.cwiseAbs().maxCoeff());
  const detail::PointsAbovePlane vertices(mesh.vertices);
  int faces = 0;  // with an area: a solid has at least four
  for (Eigen::Index f = 0; f < hull.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(hull(f, 0)), b = mesh.vertices.row(hull(f, 1)),
                          c = mesh.vertices.row(hull(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0)) continue;  // a sliver: its neighbours bound the same side
    ++faces;
    if (!vertices.any_above(a, n / len, tol)) continue;
    const double worst = ((mesh.vertices.rowwise() - a.transpose()) * (n / len)).maxCoeff();
    if (worst > tol)
      return "mesh vertex " + std::to_string(worst) + " m outside convex hull face " + std::to_string(f) +
             " (not the mesh's hull)";
  }
  if (faces < 4) return "convex hull with fewer than 4 faces of non-zero area (no volume)";
  return std::nullopt;
}

std::vector<std::string> check_shapes(const std::vector<OwnedShape>& shapes, int owner_count,
                                      const std::string& where) {
  std::vector<std::string> p;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const Shape& s = shapes[i].shape;
    const std::string el = where + "[" + std::to_string(i) + "]";
    if (shapes[i].owner < 0 || shapes[i].owner >= owner_count) p.push_back(el + ": owner index out of range");
    if (!s.size.allFinite() || !s.origin.matrix().allFinite()) p.push_back(el + ": non-finite size or pose");
    else if (!detail::is_rotation(s.origin.linear()))
      p.push_back(el + ": pose rotation is not a rotation (zero quaternion?)");
    else if (s.size.cwiseAbs().maxCoeff() > kMaxGeometryExtent ||
             s.origin.translation().cwiseAbs().maxCoeff() > kMaxGeometryExtent)
      p.push_back(el + ": size or position beyond " + std::to_string(int(kMaxGeometryExtent)) + " m");
    switch (s.type) {
      case ShapeType::Box:
        if ((s.size.array() <= 0).any()) p.push_back(el + ": box extents must be positive");
        break;
      case ShapeType::Cylinder:
        if (s.size[0] <= 0 || s.size[1] <= 0) p.push_back(el + ": cylinder radius and length must be positive");
        break;
      case ShapeType::Sphere:
        if (s.size[0] <= 0) p.push_back(el + ": sphere radius must be positive");
        break;
      case ShapeType::Mesh:
        if (s.mesh.empty()) p.push_back(el + ": mesh shape without triangles");
        if (!s.mesh.vertices.allFinite()) p.push_back(el + ": non-finite mesh vertex");
        else if (s.mesh.vertices.size() > 0 && s.mesh.vertices.cwiseAbs().maxCoeff() > kMaxGeometryExtent)
          p.push_back(el + ": mesh vertex beyond " + std::to_string(int(kMaxGeometryExtent)) + " m");
        else if (s.hull.rows() > 0) {
          if (auto why = hull_problem(s.mesh, s.hull)) p.push_back(el + ": " + *why);
        }
        break;
    }
  }
  return p;
}

}  // namespace dmgplace::formats
