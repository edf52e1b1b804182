#include "dmgplace/tools/geometry/tessellate.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace dmgplace::tools {
namespace {

TriMesh from_lists(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f) {
  TriMesh m;
  m.vertices.resize(Eigen::Index(v.size()), 3);
  m.triangles.resize(Eigen::Index(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.vertices.row(Eigen::Index(i)) = v[i].transpose();
  for (std::size_t i = 0; i < f.size(); ++i) m.triangles.row(Eigen::Index(i)) = f[i].transpose();
  return m;
}

TriMesh box(const Eigen::Vector3d& ext) {
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1 ? 0.5 : -0.5) * ext.x(), (i & 2 ? 0.5 : -0.5) * ext.y(), (i & 4 ? 0.5 : -0.5) * ext.z());
  std::vector<Eigen::Vector3i> f = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return from_lists(v, f);
}

TriMesh cylinder(double r, double len, int n) {
  // Circumscribed polygon: vertices at r / cos(pi/n) so the flat sides touch the true circle.
  const double rc = r / std::cos(M_PI / n);
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < n; ++i) {
    double a = 2 * M_PI * i / n;
    v.emplace_back(rc * std::cos(a), rc * std::sin(a), -0.5 * len);
    v.emplace_back(rc * std::cos(a), rc * std::sin(a), 0.5 * len);
  }
  v.emplace_back(0, 0, -0.5 * len);
  v.emplace_back(0, 0, 0.5 * len);
  const int b = 2 * n, t = 2 * n + 1;
  std::vector<Eigen::Vector3i> f;
  for (int i = 0; i < n; ++i) {
    int j = (i + 1) % n;
    f.emplace_back(2 * i, 2 * j, 2 * i + 1);
    f.emplace_back(2 * j, 2 * j + 1, 2 * i + 1);
    f.emplace_back(b, 2 * j, 2 * i);
    f.emplace_back(t, 2 * i + 1, 2 * j + 1);
  }
  return from_lists(v, f);
}

TriMesh sphere(double r, int n) {
  // UV sphere scaled so every face plane lies outside the true sphere (contains it).
  const int rings = std::max(4, n / 2);
  const double scale = 1.0 / (std::cos(M_PI / n) * std::cos(M_PI / (2 * rings)));
  std::vector<Eigen::Vector3d> v;
  v.emplace_back(0, 0, -r * scale);
  for (int k = 1; k < rings; ++k) {
    double phi = -M_PI / 2 + M_PI * k / rings;
    for (int i = 0; i < n; ++i) {
      double a = 2 * M_PI * i / n;
      v.emplace_back(r * scale * std::cos(phi) * std::cos(a), r * scale * std::cos(phi) * std::sin(a),
                     r * scale * std::sin(phi));
    }
  }
  v.emplace_back(0, 0, r * scale);
  std::vector<Eigen::Vector3i> f;
  const int top = int(v.size()) - 1;
  auto idx = [n](int ring, int i) { return 1 + (ring - 1) * n + (i % n); };
  for (int i = 0; i < n; ++i) f.emplace_back(0, idx(1, i + 1), idx(1, i));
  for (int k = 1; k + 1 < rings; ++k)
    for (int i = 0; i < n; ++i) {
      f.emplace_back(idx(k, i), idx(k, i + 1), idx(k + 1, i));
      f.emplace_back(idx(k, i + 1), idx(k + 1, i + 1), idx(k + 1, i));
    }
  for (int i = 0; i < n; ++i) f.emplace_back(top, idx(rings - 1, i), idx(rings - 1, i + 1));
  return from_lists(v, f);
}

}  // namespace

void append_mesh(TriMesh& into, const TriMesh& more) {
  const Eigen::Index nv = into.vertices.rows(), nt = into.triangles.rows();
  into.vertices.conservativeResize(nv + more.vertices.rows(), 3);
  into.triangles.conservativeResize(nt + more.triangles.rows(), 3);
  into.vertices.bottomRows(more.vertices.rows()) = more.vertices;
  into.triangles.bottomRows(more.triangles.rows()) = more.triangles.array() + int(nv);
}

TriMesh tessellate(const Shape& s, int segments) {
  segments = std::max(segments, 8);
  TriMesh m;
  switch (s.type) {
    case ShapeType::Box:
      m = box(s.size);
      break;
    case ShapeType::Cylinder:
      m = cylinder(s.size[0], s.size[1], segments);
      break;
    case ShapeType::Sphere:
      m = sphere(s.size[0], segments);
      break;
    case ShapeType::Mesh:
      m = s.mesh;
      break;
  }
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    m.vertices.row(i) = (s.origin * Eigen::Vector3d(m.vertices.row(i).transpose())).transpose();
  return m;
}

TriMesh tessellate(const Scene& scene, int segments) {
  TriMesh all;
  for (const auto& o : scene.objects)
    for (const auto& s : o.shapes) append_mesh(all, tessellate(s, segments));
  return all;
}

}  // namespace dmgplace::tools
