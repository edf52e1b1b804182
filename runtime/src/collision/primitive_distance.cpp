// PrimitiveObstacles::distance: the signed distance to every primitive at once, in double lanes
// (4 per vector under AVX2, 2 in the portable SSE2 build), the same formulas as
// local_signed_distance. In a scene of a few primitives (SphereFieldChecker::exact_scene) every
// body and sphere asks it, where the shape-by-shape scan with bounding-sphere culling it replaces
// had become a large share of the planner's time (docs/perf-log.md). No FMA, so both paths give the same answers.
#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/runtime/collision/primitive_obstacles.hpp"
#include "dmgplace/runtime/system/lanes.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {
namespace {

using lanes::abs;
using lanes::max;
using lanes::max0;
using lanes::min;
using lanes::sqrt;  // one instruction per lane: the file is built with -fno-math-errno

// The smallest signed distance from p to the blocks' primitives, L = 2 or 4 lanes per vector.
template <class V, class Block>
DMGPLACE_LANES_INLINE double blocks_min(const std::vector<Block>& blocks, const Eigen::Vector3d& p) {
  constexpr int L = int(sizeof(V) / sizeof(double));
  auto splat = [](double v) {
    V r;
    for (int k = 0; k < L; ++k) r[k] = v;
    return r;
  };
  auto load = [](const double* at) {
    V v;
    __builtin_memcpy(&v, at, sizeof v);
    return v;
  };
  const V px = splat(p.x()), py = splat(p.y()), pz = splat(p.z()), zero = splat(0.0);
  V best = splat(std::numeric_limits<double>::infinity());
  for (const Block& b : blocks)
    for (int h = 0; h < 4; h += L) {
      const V dx = px - load(&b.origin[0][h]), dy = py - load(&b.origin[1][h]), dz = pz - load(&b.origin[2][h]);
      auto row = [&](int r) {
        return load(&b.to_local[3 * r][h]) * dx + load(&b.to_local[3 * r + 1][h]) * dy +
               load(&b.to_local[3 * r + 2][h]) * dz;
      };
      const V lx = row(0), ly = row(1), lz = row(2);
      V d;
      if (b.type == ShapeType::Box) {
        const V qx = abs(lx) - load(&b.half[0][h]), qy = abs(ly) - load(&b.half[1][h]),
                qz = abs(lz) - load(&b.half[2][h]);
        const V ox = max0(qx), oy = max0(qy), oz = max0(qz);
        d = sqrt(ox * ox + oy * oy + oz * oz) + min(max(qx, max(qy, qz)), zero);
      } else if (b.type == ShapeType::Cylinder) {
        const V qr = sqrt(lx * lx + ly * ly) - load(&b.half[0][h]), qz = abs(lz) - load(&b.half[2][h]);
        const V orad = max0(qr), oz = max0(qz);
        d = sqrt(orad * orad + oz * oz) + min(max(qr, qz), zero);
      } else {  // a sphere (from_scene stores nothing else)
        d = sqrt(lx * lx + ly * ly + lz * lz) - load(&b.half[0][h]);
      }
      best = min(best, d);
    }
  double out = best[0];
  for (int k = 1; k < L; ++k) out = std::min(out, best[k]);
  return out;
}

}  // namespace

void PrimitiveObstacles::build_blocks() {
  blocks_.clear();
  for (const ShapeType type : {ShapeType::Box, ShapeType::Cylinder, ShapeType::Sphere}) {
    std::vector<const Primitive*> of_type;
    for (const Primitive& p : prims_)
      if (p.type == type) of_type.push_back(&p);
    for (std::size_t first = 0; first < of_type.size(); first += 4) {
      DistanceBlock b{};
      b.type = type;
      for (std::size_t lane = 0; lane < 4; ++lane) {
        const Primitive& p = *of_type[first + lane < of_type.size() ? first + lane : first];
        for (int e = 0; e < 9; ++e) b.to_local[e][lane] = p.to_local(e / 3, e % 3);
        for (int e = 0; e < 3; ++e) {
          b.origin[e][lane] = p.origin[e];
          b.half[e][lane] = p.half[e];
        }
      }
      blocks_.push_back(b);
    }
  }
}

// flatten: the kernel's lambdas are inlined too, so no vector crosses a call.
__attribute__((target("avx2"), flatten)) double PrimitiveObstacles::distance_avx2(
    const std::vector<DistanceBlock>& blocks, const Eigen::Vector3d& p) {
  return blocks_min<lanes::D>(blocks, p);
}

__attribute__((flatten)) double PrimitiveObstacles::distance_portable(const std::vector<DistanceBlock>& blocks,
                                                                      const Eigen::Vector3d& p) {
  return blocks_min<lanes::D2>(blocks, p);
}

// The smallest signed distance from each of 8 points (float lanes) to the primitives. A box's or
// cylinder's distance is sqrt(out2) outside and its inside term inside, never both nonzero; sqrt
// is monotone and correctly rounded, so the smallest of them is sqrt(min out2) + min inside: one
// root for all of them.
DMGPLACE_LANES_INLINE void PrimitiveObstacles::lanes_min(const std::vector<LanePrimitive>& prims, const float* x,
                                                         const float* y, const float* z, float* out) {
  using lanes::F;
  const F px = lanes::load(x), py = lanes::load(y), pz = lanes::load(z);
  const F inf = lanes::splatf(std::numeric_limits<float>::infinity());
  F out2 = inf, inside{}, spheres = inf;
  for (const LanePrimitive& s : prims) {
    const LaneGap g = lane_gap(s, px, py, pz);
    if (s.type == ShapeType::Sphere) {
      spheres = min(spheres, g.sphere);
    } else {
      out2 = min(out2, g.out2);
      inside = min(inside, g.inside);
    }
  }
  lanes::store(out, min(sqrt(out2) + inside, spheres));
}

// No FMA here either: both paths round alike.
__attribute__((target("avx2"), flatten)) void PrimitiveObstacles::distances_avx2(
    const std::vector<LanePrimitive>& prims, const float* x, const float* y, const float* z, float* out) {
  lanes_min(prims, x, y, z, out);
}

__attribute__((flatten)) void PrimitiveObstacles::distances_portable(const std::vector<LanePrimitive>& prims,
                                                                     const float* x, const float* y, const float* z,
                                                                     float* out) {
  lanes_min(prims, x, y, z, out);
}

void PrimitiveObstacles::distances(const float* x, const float* y, const float* z, float* out) const {
  if (simd_path() == SimdPath::Avx2) distances_avx2(lanes_, x, y, z, out);
  else distances_portable(lanes_, x, y, z, out);
}

double PrimitiveObstacles::float_error(double limit) const {
  // Each step rounds by at most 2^-24 of what it meets: coordinates up to `limit`, a primitive's
  // origin and extents up to extent(), the float rotation's entries off by 2^-24 each. The local
  // coordinates collect about 12 such roundings of limit + extent(), a distance about 45 (a
  // cylinder's, two roots deep); 64 bound them.
  return 64.0 * 0x1p-24 * (limit + extent_ + 1.0);
}

double PrimitiveObstacles::distance(const Eigen::Vector3d& p) const {
  return simd_path() == SimdPath::Avx2 ? distance_avx2(blocks_, p) : distance_portable(blocks_, p);
}

}  // namespace dmgplace::runtime
