#pragma once
// Exact signed distance to an environment made only of boxes, cylinders and spheres (MoveIt
// planning scenes usually are). The sphere layer asks it where the distance field's interpolation
// margin leaves a sphere undecided: no margin, so far fewer configurations go to FCL, and longer
// certified motions near surfaces.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::runtime {

// Signed distance from p (in the shape's parent frame) to a box, cylinder or sphere: negative
// inside. +inf for a mesh.
double shape_signed_distance(const Shape& s, const Eigen::Vector3d& p);

// Radius of the largest ball around p (in the shapes' parent frame) inside the union of `shapes`
// (inside some one of them), 0 when p is outside all. Meshes: generalised winding number for
// inside, then the distance to the nearest triangle.
double inner_radius(const std::vector<Shape>& shapes, const Eigen::Vector3d& p);

class PrimitiveObstacles {
 public:
  // Null when the scene has a mesh or scan points (their distance is the field's job).
  static std::shared_ptr<const PrimitiveObstacles> from_scene(const Scene& scene);

  // Signed distance from p to the nearest primitive (negative inside one); +inf when there are none.
  double distance(const Eigen::Vector3d& p) const;
  // Bit k set: primitive k (scene order: objects, then their shapes) comes within `radius` of p.
  // Only the first 64 primitives have bits; `all_have_bits()` says whether that is every one.
  std::uint64_t touching(const Eigen::Vector3d& p, double radius) const;
  bool all_have_bits() const { return prims_.size() <= 64; }
  std::size_t size() const { return prims_.size(); }

 private:
  struct Primitive {
    ShapeType type;
    Eigen::Matrix3d to_local;    // rotation world -> shape
    Eigen::Vector3d origin;      // shape centre in the world
    Eigen::Vector3d half;        // box: half extents; cylinder: radius, -, half length; sphere: radius
    double bound_radius = 0;     // every point of the shape is within this of `origin`
  };
  static double local_distance(const Primitive& s, const Eigen::Vector3d& p);
  std::vector<Primitive> prims_;
};

}  // namespace dmgplace::runtime
