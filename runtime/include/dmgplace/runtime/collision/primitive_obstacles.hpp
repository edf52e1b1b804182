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
#include "dmgplace/runtime/system/lanes.hpp"

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

  // Primitives (bit i: the i-th, for the first 64) whose bounding sphere comes within `need` of
  // the point in some `alive` lane (bit k: x[k], y[k], z[k]): a body's bounding sphere asks once,
  // then its spheres test only these. All ones when there are more than 64 primitives. `wide`:
  // compiled for AVX (lanes::bits).
  template <int N>
  DMGPLACE_LANES_INLINE std::uint64_t reaching_lanes(const double* x, const double* y, const double* z, double need,
                                                     std::uint32_t alive, bool wide = false) const {
    static_assert(N % lanes::W == 0);
    if (!all_have_bits()) return ~std::uint64_t(0);
    std::uint64_t mask = 0;
    for (std::size_t i = 0; i < prims_.size(); ++i)
      if (near_lanes<N>(prims_[i], x, y, z, need, wide) & alive) mask |= std::uint64_t(1) << i;
    return mask;
  }

  // Of the `alive` lanes, those at least `need` (> 0) from every primitive in `candidates`
  // (reaching_lanes; the others are known to be farther): exact, no field margin, valid anywhere.
  // One primitive at a time across all lanes (lanes.hpp vectors), squared distances (one root per
  // lane for a cylinder).
  template <int N>
  DMGPLACE_LANES_INLINE std::uint32_t clear_lanes(const double* x, const double* y, const double* z, double need,
                                                  std::uint32_t alive, std::uint64_t candidates = ~std::uint64_t(0),
                                                  bool wide = false) const {
    static_assert(N % lanes::W == 0);
    using lanes::D;
    std::uint32_t clear = alive;
    const D need2 = lanes::splat(need * need);
    for (std::size_t i = 0; i < prims_.size() && clear; ++i) {
      if (i < 64 && !(candidates >> i & 1u)) continue;
      const Primitive& s = prims_[i];
      const std::uint32_t near = near_lanes<N>(s, x, y, z, need, wide) & clear;
      if (!near) continue;
      const Eigen::Matrix3d& R = s.to_local;
      std::uint32_t far = 0;
      for (int h = 0; h < N; h += lanes::W) {
        const D dx = lanes::load(x + h) - lanes::splat(s.origin.x()), dy = lanes::load(y + h) - lanes::splat(s.origin.y()),
                dz = lanes::load(z + h) - lanes::splat(s.origin.z());
        const D px = lanes::splat(R(0, 0)) * dx + lanes::splat(R(0, 1)) * dy + lanes::splat(R(0, 2)) * dz;
        const D py = lanes::splat(R(1, 0)) * dx + lanes::splat(R(1, 1)) * dy + lanes::splat(R(1, 2)) * dz;
        const D pz = lanes::splat(R(2, 0)) * dx + lanes::splat(R(2, 1)) * dy + lanes::splat(R(2, 2)) * dz;
        D out2;  // squared distance from the shape's outside, 0 inside
        if (s.type == ShapeType::Box) {
          const D ox = lanes::max0(lanes::abs(px) - lanes::splat(s.half.x())), oy = lanes::max0(lanes::abs(py) - lanes::splat(s.half.y())),
                  oz = lanes::max0(lanes::abs(pz) - lanes::splat(s.half.z()));
          out2 = ox * ox + oy * oy + oz * oz;
        } else if (s.type == ShapeType::Cylinder) {
          const D orad = lanes::max0(lanes::sqrt(px * px + py * py) - lanes::splat(s.half.x()));
          const D oz = lanes::max0(lanes::abs(pz) - lanes::splat(s.half.z()));
          out2 = orad * orad + oz * oz;
        } else {  // a sphere (from_scene stores nothing else)
          const D o = lanes::max0(lanes::sqrt(dx * dx + dy * dy + dz * dz) - lanes::splat(s.half.x()));
          out2 = o * o;
        }
        far |= lanes::bits(out2 >= need2, wide) << h;
      }
      clear &= ~(near & ~far);
    }
    return clear;
  }

 private:
  struct Primitive {
    ShapeType type;
    Eigen::Matrix3d to_local;    // rotation world -> shape
    Eigen::Vector3d origin;      // shape centre in the world
    Eigen::Vector3d half;        // box: half extents; cylinder: radius, -, half length; sphere: radius
    double bound_radius = 0;     // every point of the shape is within this of `origin`
  };
  static double local_distance(const Primitive& s, const Eigen::Vector3d& p);
  // Lanes whose point is within need + bound_radius of the primitive's centre.
  template <int N>
  static DMGPLACE_LANES_INLINE std::uint32_t near_lanes(const Primitive& s, const double* x, const double* y, const double* z,
                                                        double need, bool wide) {
    using lanes::D;
    const D reach2 = lanes::splat((need + s.bound_radius) * (need + s.bound_radius));
    std::uint32_t near = 0;
    for (int h = 0; h < N; h += lanes::W) {
      const D dx = lanes::load(x + h) - lanes::splat(s.origin.x()), dy = lanes::load(y + h) - lanes::splat(s.origin.y()),
              dz = lanes::load(z + h) - lanes::splat(s.origin.z());
      near |= lanes::bits(dx * dx + dy * dy + dz * dz < reach2, wide) << h;
    }
    return near;
  }
  std::vector<Primitive> prims_;
};

}  // namespace dmgplace::runtime
