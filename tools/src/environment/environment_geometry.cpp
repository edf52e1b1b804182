#include "dmgplace/tools/environment/environment_geometry.hpp"

#include <algorithm>

#include "dmgplace/tools/geometry/tessellate.hpp"
#include "dmgplace/tools/io/mesh_check.hpp"

namespace dmgplace::tools {

Eigen::AlignedBox3d EnvironmentGeometry::bounds() const {
  Eigen::AlignedBox3d b;
  for (const auto& m : meshes)
    for (Eigen::Index i = 0; i < m.vertices.rows(); ++i) b.extend(Eigen::Vector3d(m.vertices.row(i).transpose()));
  for (Eigen::Index i = 0; i < points.rows(); ++i) b.extend(Eigen::Vector3d(points.row(i).transpose()));
  return b;
}

bool EnvironmentGeometry::any_closed() const { return std::find(closed.begin(), closed.end(), true) != closed.end(); }

EnvironmentGeometry make_environment_geometry(const Scene& scene, int segments) {
  EnvironmentGeometry g;
  for (const auto& o : scene.objects)
    for (const auto& s : o.shapes) {
      TriMesh m = tessellate(s, segments);
      if (m.empty()) continue;
      // Primitives tessellate closed; a mesh is closed only if every edge joins two faces.
      g.closed.push_back(s.type != ShapeType::Mesh || check_mesh(m).closed_manifold());
      g.meshes.push_back(std::move(m));
    }
  g.points = scene.points;
  return g;
}

}  // namespace dmgplace::tools
