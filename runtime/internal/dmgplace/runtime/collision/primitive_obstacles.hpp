#pragma once
// Exact signed distance to an environment made only of boxes, cylinders and spheres (MoveIt
// planning scenes usually are). The sphere layer asks it where the distance field's interpolation
// margin leaves a sphere undecided, or for every body and sphere in a scene of a few primitives
// (SphereFieldChecker::exact_scene): no margin, so far fewer configurations go to FCL, and longer
// certified motions near surfaces.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_box.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_cylinder.hpp"
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
  // The same for lanes::WF points at once (x[k], y[k], z[k]) into out[k], in floats: each within
  // float_error(limit) of distance() for a point whose coordinates are at most `limit` in
  // magnitude. Eight points per vector, where distance() takes four doubles of primitives (some
  // of them spare lanes) per point: a body's spheres ask at once (SphereFieldChecker::Pass::
  // exact_distances).
  void distances(const float* x, const float* y, const float* z, float* out) const;
  double float_error(double limit) const;
  // A primitive's separation from a point outside it: the distance, and the unit direction from
  // the primitive's nearest point to p, along which every point of the primitive lies at least
  // that distance short of p (the primitive is convex). Directional certificates use it
  // (displacement_bound.hpp).
  struct Separation {
    double distance;
    Eigen::Vector3d normal;
  };
  // Primitives whose bounding sphere comes within `within` of p, into `out` (cleared first): the
  // candidates for separations() of every point within a ball around p.
  void reaching(const Eigen::Vector3d& p, double within, std::vector<int>& out) const;
  // Every primitive of `candidates` closer to p than `within`, into `out` (cleared first). False
  // when p is inside (or on) one of them: then `out` is incomplete.
  bool separations(const Eigen::Vector3d& p, double within, const std::vector<int>& candidates,
                   std::vector<Separation>& out) const;
  // Bit k set: primitive k (scene order: objects, then their shapes) comes within `radius` of p.
  // Only the first 64 primitives have bits; `all_have_bits()` says whether that is every one.
  std::uint64_t touching(const Eigen::Vector3d& p, double radius) const;
  bool all_have_bits() const { return prims_.size() <= 64; }
  std::size_t size() const { return prims_.size(); }

  // Of the `alive` lanes, those at least `need` (> 0) from every primitive in `candidates`
  // (clear_reaching_lanes' `reach`; the others are known to be farther): exact but for float
  // rounding (the caller's margin in `need`), no field margin, valid anywhere. One primitive at a
  // time across all lanes, squared distances (one root per lane for a cylinder or sphere); only
  // the candidates' bits are visited.
  DMGPLACE_LANES_INLINE std::uint32_t clear_lanes(const float* x, const float* y, const float* z, float need,
                                                  std::uint32_t alive, std::uint64_t candidates = ~std::uint64_t(0),
                                                  bool wide = false) const {
    using lanes::F;
    using lanes::splatf;
    std::uint32_t clear = alive;
    const F need2 = splatf(need * need);
    const F qx = lanes::load(x), qy = lanes::load(y), qz = lanes::load(z);
    auto test = [&](std::size_t i) __attribute__((always_inline)) {
      const LanePrimitive& s = lanes_[i];
      const std::uint32_t near = near_lanes(s, qx, qy, qz, need, wide) & clear;
      if (near) clear &= ~(near & ~lanes::bits(outside2(s, qx, qy, qz) >= need2, wide));
    };
    if (all_have_bits()) {
      const std::uint64_t every = lanes_.size() == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << lanes_.size()) - 1;
      for (std::uint64_t left = candidates & every; left && clear; left &= left - 1)
        test(std::size_t(__builtin_ctzll(left)));
      return clear;
    }
    for (std::size_t i = 0; i < lanes_.size() && clear; ++i)
      if (i >= 64 || (candidates >> i & 1u)) test(i);
    return clear;
  }
  // clear_lanes of a body's bounding sphere (lanes::WF points x[k], y[k], z[k]), which also finds
  // the primitives its spheres may reach: `reach` gets bit i where the i-th primitive's bounding
  // sphere comes within `need` of the point in some `alive` lane (all ones past 64 primitives),
  // the `candidates` of its spheres' clear_lanes. One bounding-sphere test per primitive serves
  // both. In floats: the caller adds its rounding margin to `need`. `wide`: compiled for AVX
  // (lanes::bits).
  DMGPLACE_LANES_INLINE std::uint32_t clear_reaching_lanes(const float* x, const float* y, const float* z, float need,
                                                           std::uint32_t alive, std::uint64_t& reach,
                                                           bool wide = false) const {
    if (!all_have_bits()) {
      reach = ~std::uint64_t(0);
      return clear_lanes(x, y, z, need, alive, reach, wide);
    }
    using lanes::F;
    std::uint32_t clear = alive;
    std::uint64_t mask = 0;
    const F need2 = lanes::splatf(need * need);
    const F qx = lanes::load(x), qy = lanes::load(y), qz = lanes::load(z);
    for (std::size_t i = 0; i < lanes_.size(); ++i) {
      const LanePrimitive& s = lanes_[i];
      std::uint32_t near = near_lanes(s, qx, qy, qz, need, wide) & alive;
      if (!near) continue;
      mask |= std::uint64_t(1) << i;
      near &= clear;
      if (!near) continue;
      clear &= ~(near & ~lanes::bits(outside2(s, qx, qy, qz) >= need2, wide));
    }
    reach = mask;
    return clear;
  }
  // Largest coordinate magnitude of any primitive's points (float rounding grows with it).
  double extent() const { return extent_; }

 private:
  struct Primitive {
    ShapeType type;
    Eigen::Matrix3d to_local;  // rotation world -> shape
    Eigen::Vector3d origin;    // shape center in the world
    Eigen::Vector3d half;      // box: half extents; cylinder: radius, -, half length; sphere: radius
    double bound_radius = 0;   // every point of the shape is within this of `origin`
  };
  static double local_distance(const Primitive& s, const Eigen::Vector3d& p);
  // A primitive as the float lanes read it: rotation (row-major) and origin already in every lane
  // (a load as an operand costs less than a broadcast); the bounding radius rounded up.
  struct alignas(32) LanePrimitive {
    float to_local[9][lanes::WF], origin[3][lanes::WF];
    float half[3], bound_radius;
    ShapeType type;
    bool upright;  // turned about z only (tables, shelves): the rotation takes 4 products, not 9
  };
  static LanePrimitive to_lanes(const Primitive& p);
  // A point (every lane) against one primitive, the formulas of local_distance. A box or
  // cylinder: `out2`, the squared distance from its outside (0 inside), and `inside`, its largest
  // face offset where that is negative (0 outside). A sphere: its signed distance, `sphere`.
  struct LaneGap {
    lanes::F out2, inside, sphere;
  };
  static DMGPLACE_LANES_INLINE LaneGap lane_gap(const LanePrimitive& s, lanes::F x, lanes::F y, lanes::F z) {
    using lanes::F;
    using lanes::splatf;
    LaneGap g{};
    const F dx = x - lanes::load(s.origin[0]), dy = y - lanes::load(s.origin[1]), dz = z - lanes::load(s.origin[2]);
    if (s.type == ShapeType::Sphere) {  // (from_scene stores nothing but boxes, cylinders and spheres)
      g.sphere = lanes::sqrt(dx * dx + dy * dy + dz * dz) - splatf(s.half[0]);
      return g;
    }
    auto R = [&](int e) __attribute__((always_inline)) { return lanes::load(s.to_local[e]); };
    F px, py, pz;
    if (s.upright) {
      px = R(0) * dx + R(1) * dy, py = R(3) * dx + R(4) * dy, pz = dz;
    } else {
      px = R(0) * dx + R(1) * dy + R(2) * dz;
      py = R(3) * dx + R(4) * dy + R(5) * dz;
      pz = R(6) * dx + R(7) * dy + R(8) * dz;
    }
    const kernels::LaneGap k = s.type == ShapeType::Box ? kernels::box_gap(px, py, pz, s.half)
                                                        : kernels::cylinder_gap(px, py, pz, s.half[0], s.half[2]);
    g.out2 = k.out2;
    g.inside = k.inside;
    return g;
  }
  // The smallest signed distance from each of lanes::WF points to `prims` (distances(); defined,
  // and used, in primitive_distance.cpp).
  static DMGPLACE_LANES_INLINE void lanes_min(const std::vector<LanePrimitive>& prims, const float* x, const float* y,
                                              const float* z, float* out);
  // The squared distance from a primitive's outside in every lane (0 inside).
  static DMGPLACE_LANES_INLINE lanes::F outside2(const LanePrimitive& s, lanes::F x, lanes::F y, lanes::F z) {
    const LaneGap g = lane_gap(s, x, y, z);
    if (s.type != ShapeType::Sphere) return g.out2;
    const lanes::F o = lanes::max0(g.sphere);
    return o * o;
  }
  // Lanes whose point is within need + bound_radius of the primitive's center.
  static DMGPLACE_LANES_INLINE std::uint32_t near_lanes(const LanePrimitive& s, lanes::F x, lanes::F y, lanes::F z,
                                                        float need, bool wide) {
    using lanes::splatf;
    const float reach = need + s.bound_radius;
    const lanes::F dx = x - lanes::load(s.origin[0]), dy = y - lanes::load(s.origin[1]),
                   dz = z - lanes::load(s.origin[2]);
    return lanes::bits(dx * dx + dy * dy + dz * dz < splatf(reach * reach), wide);
  }
  std::vector<LanePrimitive> lanes_;  // prims_ in floats
  double extent_ = 0;
  std::vector<Primitive> prims_;
  // prims_ again for distance(): blocks of 4 of one type, each element in 4 double lanes (one load
  // covers the block); a block's spare lanes repeat its first primitive (primitive_distance.cpp).
  struct alignas(32) DistanceBlock {
    double to_local[9][4], origin[3][4], half[3][4];
    ShapeType type;
  };
  std::vector<DistanceBlock> blocks_;
  void build_blocks();
  static double distance_avx2(const std::vector<DistanceBlock>& blocks, const Eigen::Vector3d& p);
  static double distance_portable(const std::vector<DistanceBlock>& blocks, const Eigen::Vector3d& p);
  static void distances_avx2(const std::vector<LanePrimitive>& prims, const float* x, const float* y, const float* z,
                             float* out);
  static void distances_portable(const std::vector<LanePrimitive>& prims, const float* x, const float* y,
                                 const float* z, float* out);
};

}  // namespace dmgplace::runtime
