#pragma once
// The environment's obstacles as world-frame triangle meshes, one per collision shape, so that
// "inside" can be decided shape by shape (shapes overlap), plus scan points.
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

struct EnvironmentGeometry {
  std::vector<TriMesh> meshes;         // world frame, one per shape
  std::vector<bool> closed;            // per mesh: closed manifold, so its inside is well defined
  RowMatrixX3d points;                 // scan points, world frame
  Eigen::AlignedBox3d bounds() const;  // of all vertices and points (empty box if none)
  bool any_closed() const;
};

// Tessellates every shape (primitives circumscribed with `segments` around).
EnvironmentGeometry make_environment_geometry(const Scene& scene, int segments = 32);

}  // namespace dmgplace::tools
