#include "dmgplace/tools/validate/exact_scene_distance.hpp"

#include <algorithm>
#include <cmath>

#include "dmgplace/formats/winding_number.hpp"
#include "dmgplace/tools/environment/closest_point.hpp"

namespace dmgplace::tools {

ExactSceneDistance::ExactSceneDistance(const EnvironmentGeometry& geometry) : geometry_(&geometry) {
  for (std::size_t m = 0; m < geometry.meshes.size(); ++m) {
    const TriMesh& mesh = geometry.meshes[m];
    Eigen::AlignedBox3d box;
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
      Triangle tri{mesh.vertices.row(mesh.triangles(t, 0)).transpose(),
                   mesh.vertices.row(mesh.triangles(t, 1)).transpose(),
                   mesh.vertices.row(mesh.triangles(t, 2)).transpose(), Eigen::Vector3d::Zero(), 0};
      tri.center = (tri.a + tri.b + tri.c) / 3;
      tri.radius = std::max({(tri.a - tri.center).norm(), (tri.b - tri.center).norm(), (tri.c - tri.center).norm()});
      box.extend(tri.a), box.extend(tri.b), box.extend(tri.c);
      triangles_.push_back(tri);
    }
    closed_boxes_.push_back(geometry.closed[m] ? box : Eigen::AlignedBox3d());
  }
}

bool ExactSceneDistance::inside(const Eigen::Vector3d& p) const {
  for (std::size_t m = 0; m < closed_boxes_.size(); ++m)
    if (!closed_boxes_[m].isEmpty() && closed_boxes_[m].contains(p) &&
        std::abs(winding_number(geometry_->meshes[m], p)) > 0.5)
      return true;
  return false;
}

double ExactSceneDistance::signed_distance(const Eigen::Vector3d& p, double cap) const {
  const double d = unsigned_distance(p, cap);
  return inside(p) ? -d : d;
}

double ExactSceneDistance::unsigned_distance(const Eigen::Vector3d& p, double cap) const {
  double best = cap;
  for (const auto& t : triangles_) {
    const double reach = best + t.radius;
    if ((p - t.center).squaredNorm() >= reach * reach) continue;
    best = std::min(best, std::sqrt(squared_distance_to_triangle(p, t.a, t.b, t.c)));
  }
  const auto& pts = geometry_->points;
  for (Eigen::Index i = 0; i < pts.rows(); ++i) best = std::min(best, (pts.row(i).transpose() - p).norm());
  return best;
}

double ExactSceneDistance::distance_above(const Eigen::Vector3d& p, double cap, double z_min) const {
  double best = cap;
  for (const auto& t : triangles_) {
    const double reach = best + t.radius;
    if (t.center.z() + t.radius <= z_min || (p - t.center).squaredNorm() >= reach * reach) continue;
    best = std::min(best, std::sqrt(squared_distance_to_triangle_above(p, t.a, t.b, t.c, z_min)));
  }
  const auto& pts = geometry_->points;
  for (Eigen::Index i = 0; i < pts.rows(); ++i)
    if (pts(i, 2) > z_min) best = std::min(best, (pts.row(i).transpose() - p).norm());
  return best;
}

}  // namespace dmgplace::tools
