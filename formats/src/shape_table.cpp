#include "dmgplace/formats/shape_table.hpp"

#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "format_util.hpp"

namespace dmgplace::formats {

void pose_to_array(const Eigen::Isometry3d& pose, double* out) {
  Eigen::Quaterniond q(pose.rotation());
  q.normalize();
  out[0] = pose.translation().x(); out[1] = pose.translation().y(); out[2] = pose.translation().z();
  out[3] = q.x(); out[4] = q.y(); out[5] = q.z(); out[6] = q.w();
}

Eigen::Isometry3d pose_from_array(const double* in, const std::string& file, const std::string& element) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond q(in[6], in[3], in[4], in[5]);
  // Writers store unit quaternions. A zero one would silently read as the identity (every term of
  // the rotation matrix is a product of two components) and a NaN one as garbage: refuse both.
  if (!(std::abs(q.norm() - 1) <= 1e-6)) throw Error(file, element, "pose quaternion is not of unit length (zero or corrupt)");
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
  std::vector<std::int32_t> tris;
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
  }
  w.write(g + "/type", std::span<const std::int32_t>(type), {k});
  w.write(g + "/owner", std::span<const std::int32_t>(owner), {k});
  w.write(g + "/size", std::span<const double>(size), {k, 3});
  w.write(g + "/pose", std::span<const double>(pose), {k, 7});
  w.write(g + "/mesh_ranges", std::span<const std::int64_t>(ranges), {k, 4});
  w.write(g + "/mesh_vertices", std::span<const double>(verts), {verts.size() / 3, 3});
  w.write(g + "/mesh_triangles", std::span<const std::int32_t>(tris), {tris.size() / 3, 3});
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
  std::vector<OwnedShape> out(static_cast<std::size_t>(k));
  for (long i = 0; i < k; ++i) {
    auto& o = out[std::size_t(i)];
    const std::string el = g + "[" + std::to_string(i) + "]";
    if (type.data[i] < 0 || type.data[i] > 3) throw Error(r.file(), el, "unknown shape type " + std::to_string(type.data[i]));
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
  }
  return out;
}

std::vector<std::string> check_shapes(const std::vector<OwnedShape>& shapes, int owner_count, const std::string& where) {
  std::vector<std::string> p;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const Shape& s = shapes[i].shape;
    const std::string el = where + "[" + std::to_string(i) + "]";
    if (shapes[i].owner < 0 || shapes[i].owner >= owner_count) p.push_back(el + ": owner index out of range");
    if (!s.size.allFinite() || !s.origin.matrix().allFinite()) p.push_back(el + ": non-finite size or pose");
    else if (!detail::is_rotation(s.origin.linear())) p.push_back(el + ": pose rotation is not a rotation (zero quaternion?)");
    else if (s.size.cwiseAbs().maxCoeff() > kMaxGeometryExtent || s.origin.translation().cwiseAbs().maxCoeff() > kMaxGeometryExtent)
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
        break;
    }
  }
  return p;
}

}  // namespace dmgplace::formats
