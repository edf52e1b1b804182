#pragma once
// A triangle mesh in an Embree BVH (private to dmgplace_tools): ray casts and exact box overlap
// tests (Embree point query for candidates, separating-axis test in double precision).
#include <Eigen/Geometry>
#include <optional>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools::detail {

// An oriented box: center, rotation (columns = box axes) and half extents.
struct OrientedBox {
  Eigen::Vector3d center;
  Eigen::Matrix3d axes;
  Eigen::Vector3d half;
};

struct RayHit {
  double distance = 0;
  int triangle = -1;
};

class EmbreeMesh {
 public:
  explicit EmbreeMesh(const TriMesh& mesh);  // the mesh must outlive this object
  ~EmbreeMesh();
  EmbreeMesh(const EmbreeMesh&) = delete;
  EmbreeMesh& operator=(const EmbreeMesh&) = delete;

  // First triangle hit along origin + t * dir (dir unit), t in [0, max_distance].
  std::optional<RayHit> cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double max_distance) const;
  // True when any triangle intersects the closed box.
  bool overlaps(const OrientedBox& box) const;

 private:
  const TriMesh& mesh_;
  void* device_ = nullptr;  // RTCDevice / RTCScene kept opaque: Embree headers stay in the .cpp
  void* scene_ = nullptr;
};

// Exact triangle / axis-aligned box overlap (box centered at the origin with half extents h).
bool triangle_overlaps_box(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& h);

}  // namespace dmgplace::tools::detail
