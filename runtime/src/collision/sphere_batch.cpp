// SphereFieldChecker::free_lanes: the fast layer's "proven free" for 8 configurations at once.
// Every step runs in floats across all 8 lanes (lanes::F, one AVX register): forward kinematics
// (Kinematics::frame_poses_batch into a PoseBatchF, the bodies carried into their batch frames),
// then one body or sphere at a time: centres, bounds, exact primitive distances, pair distances.
// Every test that can say "free" adds a rounding margin (lane_margin(): the kinematics' own error
// bound and the steps after it; a pair test adds a second pose error, one per body), so the
// floats stay conservative. Only the field loads are one per lane. Compiled for AVX2 + FMA and
// for the portable baseline, chosen at run time (system/simd_dispatch).
#include <algorithm>
#include <array>
#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/system/lanes.hpp"
#include "dmgplace/runtime/collision/kernels/lane_points.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_field.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_sphere.hpp"
#include "sphere_lane_motion.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {
namespace {

constexpr int N = PoseBatch::kLanes;
static_assert(N == lanes::WF, "one float vector per coordinate");
using lanes::F;
using lanes::splatf;
using Xyz = LaneXyz;
// The lane kernels (collision/kernels/): one job each, tested against exact answers.
using kernels::clear_of_field;
using kernels::overlaps;
using kernels::PoseLanes;
using kernels::transform;
using kernels::within;

}  // namespace

// Table::lower_bound for 8 configurations, four at a time in double lanes: the same nearest
// node (clamped), loss and value, so the same answers as the scalar lookup.
inline __attribute__((always_inline)) std::uint32_t SphereFieldChecker::Table::apart_lanes(const double* const* q, double padding,
                                                                                            bool wide) const {
  using lanes::D;
  typedef int I __attribute__((vector_size(4 * sizeof(int))));
  std::uint32_t out = 0;
  for (int h = 0; h < N; h += lanes::W) {
    D loss{};
    I index{};
    for (std::size_t k = 0; k < 2; ++k) {
      const int at = slot[k];
      const D x = at >= 0 ? D{q[h][at], q[h + 1][at], q[h + 2][at], q[h + 3][at]} : D{};
      const D lower = lanes::splat(data.lower[k]);
      D u = (x - lower) * lanes::splat(inv_step[k]);
      u = u > D{} ? u : D{};  // also maps NaN to 0
      u = lanes::min(u, lanes::splat(double(data.count[k] - 1)));
      const I i = __builtin_convertvector(u + lanes::splat(0.5), I);  // u >= 0: truncation rounds
      loss += lanes::splat(data.slope[k]) * lanes::abs(x - (lower + __builtin_convertvector(i, D) * lanes::splat(data.step[k])));
      index = index * data.count[k] + i;
    }
    const D value = D{double(tenths_mm[std::size_t(index[0])]), double(tenths_mm[std::size_t(index[1])]),
                      double(tenths_mm[std::size_t(index[2])]), double(tenths_mm[std::size_t(index[3])])};
    out |= lanes::bits((lanes::M)(lanes::splat(1e-4) * value - loss - lanes::splat(padding) > D{}), wide) << h;
  }
  return out;
}

void SphereFieldChecker::set_lane_bounds() {
  const double scene =
      std::max({2.0, lo_.cwiseAbs().maxCoeff(), hi_.cwiseAbs().maxCoeff(), obstacles_ ? obstacles_->extent() : 0.0});
  lane_limit_ = std::max(scene, reach_);
  // Every float step rounds by at most 2^-24 of the magnitudes it meets: coordinates up to
  // lane_limit_ (body centres past it drop their lane), sphere offsets within reach_, primitive
  // extents. A pose element, a transform, a difference, a rotation into a primitive's frame and a
  // squared distance each add a few such roundings; 64 of them bound the lot with room to spare.
  // Forward kinematics in floats adds its own bound, for points as far from their link's origin
  // as any sphere's far side.
  lane_rounding_ = 64.0 * 0x1p-24 * (lane_limit_ + 2.0 * reach_ + 1.0);
  // |p - from| <= 2 (lane_limit_ + reach_) and |d| <= 2 reach_ there (every point of a body is
  // within reach_ of its centre).
  capsule_rounding_ = lanes::kSegmentRounding * 0x1p-24 * (2.0 * lane_limit_ + 4.0 * reach_ + 1.0);
  exact_float_error_ = obstacles_ ? obstacles_->float_error(lane_limit_) : 0.0;
}

double SphereFieldChecker::lane_margin() const {
  // The kinematics' float error bound as it is now: setting a joint outside the chain
  // (Kinematics::set_joint_value) rebuilds it, so it is asked per batch, not kept.
  return lane_rounding_ + kin_->float_pose_error(link_reach_);
}

void SphereFieldChecker::set_exact_obstacles(std::shared_ptr<const PrimitiveObstacles> obstacles) {
  if (!fine_ && (!obstacles || !obstacles->all_have_bits()))
    throw Error("SphereFieldChecker", "scene", "a checker without a distance field needs at most 64 exact primitives");
  obstacles_ = std::move(obstacles);
  set_lane_bounds();
}

inline __attribute__((always_inline)) std::uint32_t SphereFieldChecker::free_lanes_body(const SphereFieldChecker& c,
                                                                                        const double* const* q, int count,
                                                                                        const float* widen,
                                                                                        const LaneMotion* motion, bool wide) {
  const double* in[N];
  for (int k = 0; k < N; ++k) in[k] = q[k < count ? k : 0];  // idle lanes repeat the first
  // The bodies in their batch frames (FK then skips the links no chain joint moves) unless a
  // joint value was set since they were carried there.
  const BatchBodies& at = c.batch_bodies();
  thread_local PoseBatchF poses;
  if (&at == &c.framed_) c.kin_->frame_poses_batch(in, poses);
  else c.kin_->link_poses_batch(in, poses);
  const std::uint32_t all = (1u << count) - 1;
  std::uint32_t alive = all;
  thread_local std::vector<Xyz> world, centre, cap_from, cap_dir;
  thread_local std::vector<char> done;  // per body: 1 its spheres' centres, 2 its capsule, are in the world
  world.resize(c.spheres_.size());
  centre.resize(c.bodies_.size());
  cap_from.resize(c.bodies_.size());
  cap_dir.resize(c.bodies_.size());
  done.assign(c.bodies_.size(), 0);
  const float margin = float(c.lane_margin()), limit = float(c.lane_limit_);
  // A pair's two spheres (or bounding spheres) each carry their own link's pose error.
  const float pair_margin = float(c.lane_margin() + c.kin_->float_pose_error(c.link_reach_));
  auto spheres_of = [&](std::size_t bi) {
    if (done[bi] & 1) return;
    const Body& b = c.bodies_[bi];
    const PoseLanes pose(poses.pose[std::size_t(at.link[bi])]);
    for (int i = b.begin; i < b.end; ++i) {
      const LaneSphere& l = at.spheres[std::size_t(i)];
      transform(pose, lanes::load(l.x), lanes::load(l.y), lanes::load(l.z), world[std::size_t(i)]);
    }
    done[bi] |= 1;
  };
  // A body's capsule in the world: its first end and the segment from it (both ends transformed,
  // so the segment's ends carry the same pose error as any point of the body).
  auto capsule_of = [&](std::size_t bi) __attribute__((always_inline)) {
    if (done[bi] & 2) return;
    const Capsule& k = at.capsule[bi];
    const PoseLanes pose(poses.pose[std::size_t(at.link[bi])]);
    Xyz to;
    transform(pose, splatf(float(k.from.x())), splatf(float(k.from.y())), splatf(float(k.from.z())), cap_from[bi]);
    transform(pose, splatf(float(k.to.x())), splatf(float(k.to.y())), splatf(float(k.to.z())), to);
    lanes::store(cap_dir[bi].x, lanes::load(to.x) - lanes::load(cap_from[bi].x));
    lanes::store(cap_dir[bi].y, lanes::load(to.y) - lanes::load(cap_from[bi].y));
    lanes::store(cap_dir[bi].z, lanes::load(to.z) - lanes::load(cap_from[bi].z));
    done[bi] |= 2;
  };
  // Body bi's capsule in registers, and the lanes where a point is nearer than `reach` to it.
  const float capsule_margin = float(c.capsule_rounding_);
  struct CapsuleLanes {
    F fx, fy, fz, dx, dy, dz, inv_len2;
    float radius;
  };
  auto capsule_lanes = [&](std::size_t bi) __attribute__((always_inline)) {
    capsule_of(bi);
    const Xyz &f = cap_from[bi], &d = cap_dir[bi];
    const Body& b = c.bodies_[bi];
    return CapsuleLanes{lanes::load(f.x), lanes::load(f.y), lanes::load(f.z), lanes::load(d.x), lanes::load(d.y),
                        lanes::load(d.z), splatf(float(b.inv_len2)), float(at.capsule[bi].radius) + capsule_margin};
  };
  auto near_capsule = [&](const Xyz& p, const CapsuleLanes& k, float reach) __attribute__((always_inline)) {
    const float r = reach + k.radius;
    return lanes::bits(lanes::near_segment(lanes::load(p.x), lanes::load(p.y), lanes::load(p.z), k.fx, k.fy, k.fz, k.dx,
                                           k.dy, k.dz, k.inv_len2, splatf(r * r)),
                       wide);
  };
  // A scene of primitives is tested exactly, in cache: a body's bounding sphere finds the
  // primitives it may reach, its spheres test only those. Otherwise the distance field.
  const PrimitiveObstacles* prims = c.obstacles_.get();
  std::uint64_t reach = ~std::uint64_t(0);
  const std::size_t nb = c.bodies_.size();
  auto widened = [&](std::size_t k) __attribute__((always_inline)) { return widen ? widen[k] : 0.0f; };
  float body_widen = 0;  // the current body's
  auto clear_lanes = [&](const Xyz& p, double r, std::uint32_t lanes) __attribute__((always_inline)) {
    const double need = r + c.padding_ + margin + body_widen;
    if (prims) return prims->clear_lanes(p.x, p.y, p.z, float(need), lanes, reach, wide);
    return clear_of_field(p, float(need), margin, lanes, c.lo_, c.hi_, c.coarse_.get(), *c.fine_, wide);
  };
  // A body's bounding sphere: with primitives, also the ones its spheres may reach (`reach`).
  auto clear_body = [&](const Xyz& p, double r, std::uint32_t lanes) __attribute__((always_inline)) {
    if (!prims) return clear_lanes(p, r, lanes);
    return prims->clear_reaching_lanes(p.x, p.y, p.z, float(r + c.padding_ + margin + body_widen), lanes, reach, wide);
  };
  lanes::MF in_range = ~lanes::MF{};
  for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi) {
    const Body& b = c.bodies_[bi];
    const Eigen::Vector3d& bc = at.center[bi];
    transform(PoseLanes(poses.pose[std::size_t(at.link[bi])]), splatf(float(bc.x())), splatf(float(bc.y())),
              splatf(float(bc.z())), centre[bi]);
    in_range &= within(centre[bi], limit);
    if (!b.moving && !b.attached) continue;
    body_widen = widened(bi);
    std::uint32_t open = alive & ~clear_body(centre[bi], b.radius, alive);
    // Undecided under the static bound: the lanes' own (sphere_lane_motion.hpp), where smaller.
    if (open && motion && body_widen > 0) {
      const float local = motion->body(c, bi, poses, centre.data(), open);
      if (local < body_widen) {
        body_widen = local;
        open &= ~clear_body(centre[bi], b.radius, open);
      }
    }
    if (!open) continue;
    spheres_of(bi);
    for (int i = b.begin; i < b.end && open; ++i) {
      const std::uint32_t ok = clear_lanes(world[std::size_t(i)], c.spheres_[std::size_t(i)].radius, open);
      alive &= ~(open & ~ok);
      open &= ok;
    }
    if (!alive) return 0;
  }
  alive &= lanes::bits(in_range, wide);
  for (std::size_t pi = 0; pi < c.pairs_.size(); ++pi) {
    if (!alive) return 0;
    const Pair& p = c.pairs_[pi];
    float pair_widen = widened(nb + pi);
    const Xyz &ca = centre[std::size_t(p.a)], &cb = centre[std::size_t(p.b)];
    std::uint32_t near = lanes::bits(overlaps(ca, cb, float(p.reach) + pair_margin + pair_widen), wide) & alive;
    if (!near) continue;
    // A pair with a table asks it first, the pair's motion over the reach bounded by the smaller
    // of its static widening and the table's own slopes times its joints' travel: the wrist pairs
    // near in every lane are settled there without the lanes' lever arms (LaneMotion::pair).
    const Table* table = p.table >= 0 ? &(*c.tables_)[std::size_t(p.table)] : nullptr;
    const double travel = table && motion ? motion->table_travel(*table) : 0.0;
    auto table_apart = [&](std::uint32_t lanes) __attribute__((always_inline)) {
      return lanes & table->apart_lanes(in, c.padding_ + std::min(double(pair_widen), travel), wide);
    };
    if (table) near &= ~table_apart(near);
    // Near under the static bound: the lanes' own, where smaller (as for bodies).
    if (near && motion && pair_widen > 0) {
      const float local = motion->pair(c, pi, poses, centre.data(), near);
      if (local < pair_widen) {
        pair_widen = local;
        near &= lanes::bits(overlaps(ca, cb, float(p.reach) + pair_margin + pair_widen), wide);
        if (table && near && double(pair_widen) < travel) near &= ~table_apart(near);
      }
    }
    if (!near) continue;
    const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
    // A long body's capsule against the other's bounding sphere, each way.
    const float pad = float(c.padding_) + pair_margin + pair_widen;
    CapsuleLanes kb{};
    if (b.has_capsule) {
      kb = capsule_lanes(std::size_t(p.b));
      near &= near_capsule(ca, kb, float(a.radius) + pad);
    }
    if (near && a.has_capsule) near &= near_capsule(cb, capsule_lanes(std::size_t(p.a)), float(b.radius) + pad);
    if (!near) continue;
    spheres_of(std::size_t(p.a));
    spheres_of(std::size_t(p.b));
    std::uint32_t hit = 0;
    lanes::MF acc{};
    for (int i = a.begin; i < a.end; ++i) {
      const Xyz& wa = world[std::size_t(i)];
      const float ra = float(c.spheres_[std::size_t(i)].radius + c.padding_) + pair_margin + pair_widen;
      // A sphere clear of b's bounding sphere (or capsule) in every lane still open cannot touch
      // b's spheres.
      const std::uint32_t open = near & ~hit;
      if (!((b.has_capsule ? near_capsule(wa, kb, ra) : lanes::bits(overlaps(wa, cb, ra + float(b.radius)), wide)) & open))
        continue;
      // The same float sums and squares as ra + r_j in scalars, all lanes at once.
      const F rav = splatf(ra);
      auto touches = [&](int j) __attribute__((always_inline)) {
        const F reach = rav + lanes::load(at.spheres[std::size_t(j)].r);
        return overlaps(wa, world[std::size_t(j)], reach * reach);
      };
      if (wide) {
        for (int j = b.begin; j < b.end; ++j) acc |= touches(j);
        hit = lanes::bits(acc, wide);
      } else {
        for (int j = b.begin; j < b.end; ++j) hit |= lanes::bits(touches(j), wide);
      }
      if ((hit & near) == near) break;
    }
    alive &= ~(hit & near);
  }
  return alive & all;
}

// flatten: lanes::movemask_avx (AVX only, so not always_inline) is inlined here too; left to the
// inliner, this function is past its size limits and each mask became a call.
__attribute__((target("avx2,fma"), flatten)) std::uint32_t SphereFieldChecker::free_lanes_avx2(const SphereFieldChecker& c,
                                                                                               const double* const* q,
                                                                                               int count, const float* widen,
                                                                                               const LaneMotion* motion) {
  return free_lanes_body(c, q, count, widen, motion, true);
}

std::uint32_t SphereFieldChecker::free_lanes_portable(const SphereFieldChecker& c, const double* const* q, int count,
                                                      const float* widen, const LaneMotion* motion) {
  return free_lanes_body(c, q, count, widen, motion, false);
}

std::uint32_t SphereFieldChecker::free_lanes(const double* const* q, int count) const {
  if (count <= 0) return 0;
  count = std::min(count, N);
  return simd_path() == SimdPath::Avx2 ? free_lanes_avx2(*this, q, count, nullptr, nullptr)
                                       : free_lanes_portable(*this, q, count, nullptr, nullptr);
}

}  // namespace dmgplace::runtime
