#pragma once
// Distances to an environment's obstacles by brute force over every triangle and scan point,
// independent of the Embree BVH the bake queries: what `validate --deep` holds a stored field
// against. Triangles are skipped by their bounding spheres, so a query costs one comparison per
// triangle beyond the few near it.
#include <Eigen/Core>
#include <vector>

#include "dmgplace/tools/environment/environment_geometry.hpp"

namespace dmgplace::tools {

class ExactSceneDistance {
 public:
  // Keeps a pointer to `geometry`, which must outlive this object.
  explicit ExactSceneDistance(const EnvironmentGeometry& geometry);

  // Distance from p to the nearest triangle or point, at most `cap` (cap when nothing is nearer);
  // negative inside a closed mesh.
  double signed_distance(const Eigen::Vector3d& p, double cap) const;
  double unsigned_distance(const Eigen::Vector3d& p, double cap) const;
  // Distance from p to the obstacle parts strictly above height z_min, at most `cap`, whether or
  // not p is inside.
  double distance_above(const Eigen::Vector3d& p, double cap, double z_min) const;
  // Inside a closed mesh: its generalised winding number is non-zero (the bake's rule, whatever
  // the mesh's orientation).
  bool inside(const Eigen::Vector3d& p) const;

 private:
  struct Triangle {
    Eigen::Vector3d a, b, c, center;
    double radius;
  };
  const EnvironmentGeometry* geometry_;
  std::vector<Triangle> triangles_;
  std::vector<Eigen::AlignedBox3d> closed_boxes_;  // per mesh; empty box when the mesh is open
};

}  // namespace dmgplace::tools
