#pragma once
// One free_lanes query on 8 configurations (SphereFieldChecker::free_lanes_body): the link poses
// in float lanes, and what has been carried into the world so far (sphere centers, body centers,
// capsules: each on first use), read by two passes: every body against the scene (environment),
// then the self pairs. Each test is a lane kernel of collision/kernels/; every member is
// always_inline, so a query still compiles to one function. Private to the runtime.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "dmgplace/runtime/collision/kernels/lane_points.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_capsule.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_field.hpp"
#include "dmgplace/runtime/collision/kernels/sphere_sphere.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/system/lanes.hpp"
#include "sphere_lane_motion.hpp"

#define DMGPLACE_LANE_PASS_INLINE inline __attribute__((always_inline))

namespace dmgplace::runtime {

struct SphereFieldChecker::LanePass {
  static constexpr int N = LinkPoseLanesD::kLanes;
  static_assert(N == lanes::WF, "one float vector per coordinate");
  using F = lanes::F;
  using Xyz = LaneXyz;

  // Per-thread scratch, sized per query: no allocation once warm.
  struct Scratch {
    LinkPoseLanesF poses;
    std::vector<Xyz> world, center, cap_from, cap_dir;
    std::vector<char> done;  // per body: 1 its spheres' centers, 2 its capsule, are in the world
  };
  static Scratch& scratch() {
    thread_local Scratch s;
    return s;
  }

  const SphereFieldChecker& c;
  const LaneMotion* motion;
  const float* widen;  // per body, then per pair: the static widening (null: none)
  bool wide;
  const double* in[N];
  const LaneBodies& at;
  Scratch& s;
  const std::uint32_t all;
  std::uint32_t alive;
  float margin, limit, pair_margin, capsule_margin;
  // A scene of primitives is tested exactly, in cache: a body's bounding sphere finds the
  // primitives it may reach (`reach`), its spheres test only those. Otherwise the distance field.
  const PrimitiveObstacles* prims;
  std::uint64_t reach = ~std::uint64_t(0);
  float body_widen = 0;  // the current body's

  DMGPLACE_LANE_PASS_INLINE LanePass(const SphereFieldChecker& checker, const double* const* q, int count,
                                     const float* w, const LaneMotion* m, bool wide_lanes)
      : c(checker), motion(m), widen(w), wide(wide_lanes), at(checker.lane_bodies()), s(scratch()),
        all((1u << count) - 1), alive(all), prims(checker.obstacles_.get()) {
    for (int k = 0; k < N; ++k) in[k] = q[k < count ? k : 0];  // idle lanes repeat the first
    // The bodies in their lane frames (FK then skips the links no chain joint moves) unless a
    // joint value was set since they were carried there.
    if (&at == &c.framed_) c.kin_->lanes().frame_poses(in, s.poses);
    else c.kin_->lanes().link_poses(in, s.poses);
    s.world.resize(c.spheres_.size());
    s.center.resize(c.bodies_.size());
    s.cap_from.resize(c.bodies_.size());
    s.cap_dir.resize(c.bodies_.size());
    s.done.assign(c.bodies_.size(), 0);
    margin = float(c.lane_margin());
    limit = float(c.lane_limit_);
    // A pair's two spheres (or bounding spheres) each carry their own link's pose error.
    pair_margin = float(c.lane_margin() + c.kin_->lanes().float_pose_error(c.link_reach_));
    capsule_margin = float(c.capsule_rounding_);
  }

  DMGPLACE_LANE_PASS_INLINE kernels::PoseLanes pose_of(std::size_t bi) const {
    return kernels::PoseLanes(s.poses.pose[std::size_t(at.link[bi])]);
  }
  DMGPLACE_LANE_PASS_INLINE float widened(std::size_t k) const { return widen ? widen[k] : 0.0f; }

  DMGPLACE_LANE_PASS_INLINE void spheres_of(std::size_t bi) {
    if (s.done[bi] & 1) return;
    const Body& b = c.bodies_[bi];
    const kernels::PoseLanes pose = pose_of(bi);
    for (int i = b.begin; i < b.end; ++i) {
      const LaneSphere& l = at.spheres[std::size_t(i)];
      kernels::transform(pose, lanes::load(l.x), lanes::load(l.y), lanes::load(l.z), s.world[std::size_t(i)]);
    }
    s.done[bi] |= 1;
  }

  // A body's capsule in the world: its first end and the segment from it (both ends transformed,
  // so the segment's ends carry the same pose error as any point of the body).
  DMGPLACE_LANE_PASS_INLINE void capsule_of(std::size_t bi) {
    if (s.done[bi] & 2) return;
    const Capsule& k = at.capsule[bi];
    const kernels::PoseLanes pose = pose_of(bi);
    Xyz to;
    kernels::transform(pose, lanes::splatf(float(k.from.x())), lanes::splatf(float(k.from.y())),
                       lanes::splatf(float(k.from.z())), s.cap_from[bi]);
    kernels::transform(pose, lanes::splatf(float(k.to.x())), lanes::splatf(float(k.to.y())),
                       lanes::splatf(float(k.to.z())), to);
    lanes::store(s.cap_dir[bi].x, lanes::load(to.x) - lanes::load(s.cap_from[bi].x));
    lanes::store(s.cap_dir[bi].y, lanes::load(to.y) - lanes::load(s.cap_from[bi].y));
    lanes::store(s.cap_dir[bi].z, lanes::load(to.z) - lanes::load(s.cap_from[bi].z));
    s.done[bi] |= 2;
  }

  // Body bi's capsule in registers, and the lanes where a point is nearer than `reach` to it.
  struct CapsuleLanes {
    F fx, fy, fz, dx, dy, dz, inv_len2;
    float radius;
  };
  DMGPLACE_LANE_PASS_INLINE CapsuleLanes capsule_lanes(std::size_t bi) {
    capsule_of(bi);
    const Xyz &f = s.cap_from[bi], &d = s.cap_dir[bi];
    return CapsuleLanes{lanes::load(f.x),
                        lanes::load(f.y),
                        lanes::load(f.z),
                        lanes::load(d.x),
                        lanes::load(d.y),
                        lanes::load(d.z),
                        lanes::splatf(float(c.bodies_[bi].inv_len2)),
                        float(at.capsule[bi].radius) + capsule_margin};
  }
  DMGPLACE_LANE_PASS_INLINE std::uint32_t near_capsule(const Xyz& p, const CapsuleLanes& k, float reach_to) const {
    const float r = reach_to + k.radius;
    return lanes::bits(kernels::near_segment(lanes::load(p.x), lanes::load(p.y), lanes::load(p.z), k.fx, k.fy, k.fz,
                                             k.dx, k.dy, k.dz, k.inv_len2, lanes::splatf(r * r)),
                       wide);
  }

  // Lanes where a sphere at p of radius r is clear of the scene.
  DMGPLACE_LANE_PASS_INLINE std::uint32_t clear_lanes(const Xyz& p, double r, std::uint32_t lanes) {
    const double need = r + c.padding_ + margin + body_widen;
    if (prims) return prims->clear_lanes(p.x, p.y, p.z, float(need), lanes, reach, wide);
    return kernels::clear_of_field(p, float(need), margin, lanes, c.lo_, c.hi_, c.coarse_.get(), *c.fine_, wide);
  }
  // A body's bounding sphere: with primitives, also the ones its spheres may reach (`reach`).
  DMGPLACE_LANE_PASS_INLINE std::uint32_t clear_body(const Xyz& p, double r, std::uint32_t lanes) {
    if (!prims) return clear_lanes(p, r, lanes);
    return prims->clear_reaching_lanes(p.x, p.y, p.z, float(r + c.padding_ + margin + body_widen), lanes, reach, wide);
  }

  // Every moving (or attached) body against the scene: its bounding sphere, then its spheres.
  // Also places every body's center and drops the lanes whose centers leave lane_limit_. False
  // when no lane is left.
  DMGPLACE_LANE_PASS_INLINE bool environment() {
    lanes::MF in_range = ~lanes::MF{};
    for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi) {
      const Body& b = c.bodies_[bi];
      const Eigen::Vector3d& bc = at.center[bi];
      kernels::transform(pose_of(bi), lanes::splatf(float(bc.x())), lanes::splatf(float(bc.y())),
                         lanes::splatf(float(bc.z())), s.center[bi]);
      in_range &= kernels::within(s.center[bi], limit);
      if (!b.moving && !b.attached) continue;
      body_widen = widened(bi);
      std::uint32_t open = alive & ~clear_body(s.center[bi], b.radius, alive);
      // Undecided under the static bound: the lanes' own (sphere_lane_motion.hpp), where smaller.
      if (open && motion && body_widen > 0) {
        const float local = motion->body(c, bi, s.poses, s.center.data(), open);
        if (local < body_widen) {
          body_widen = local;
          open &= ~clear_body(s.center[bi], b.radius, open);
        }
      }
      if (!open) continue;
      spheres_of(bi);
      for (int i = b.begin; i < b.end && open; ++i) {
        const std::uint32_t ok = clear_lanes(s.world[std::size_t(i)], c.spheres_[std::size_t(i)].radius, open);
        alive &= ~(open & ~ok);
        open &= ok;
      }
      if (!alive) return false;
    }
    alive &= lanes::bits(in_range, wide);
    return true;
  }

  // Pair pi's lanes still near after its cheap tests: the bounding spheres, the pair's table
  // (where it has one) and the capsules; kb is b's capsule where b has one.
  DMGPLACE_LANE_PASS_INLINE std::uint32_t pair_near(std::size_t pi, float& pair_widen, CapsuleLanes& kb) {
    const Pair& p = c.pairs_[pi];
    const Xyz &ca = s.center[std::size_t(p.a)], &cb = s.center[std::size_t(p.b)];
    std::uint32_t near =
        lanes::bits(kernels::overlaps(ca, cb, float(p.reach) + pair_margin + pair_widen), wide) & alive;
    if (!near) return 0;
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
      const float local = motion->pair(c, pi, s.poses, s.center.data(), near);
      if (local < pair_widen) {
        pair_widen = local;
        near &= lanes::bits(kernels::overlaps(ca, cb, float(p.reach) + pair_margin + pair_widen), wide);
        if (table && near && double(pair_widen) < travel) near &= ~table_apart(near);
      }
    }
    if (!near) return 0;
    const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
    // A long body's capsule against the other's bounding sphere, each way.
    const float pad = float(c.padding_) + pair_margin + pair_widen;
    if (b.has_capsule) {
      kb = capsule_lanes(std::size_t(p.b));
      near &= near_capsule(ca, kb, float(a.radius) + pad);
    }
    if (near && a.has_capsule) near &= near_capsule(cb, capsule_lanes(std::size_t(p.a)), float(b.radius) + pad);
    return near;
  }

  // The lanes of `near` where a sphere of pair pi's body a touches one of body b's.
  DMGPLACE_LANE_PASS_INLINE std::uint32_t pair_hits(std::size_t pi, std::uint32_t near, float pair_widen,
                                                    const CapsuleLanes& kb) {
    const Pair& p = c.pairs_[pi];
    const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
    const Xyz& cb = s.center[std::size_t(p.b)];
    spheres_of(std::size_t(p.a));
    spheres_of(std::size_t(p.b));
    std::uint32_t hit = 0;
    lanes::MF acc{};
    for (int i = a.begin; i < a.end; ++i) {
      const Xyz& wa = s.world[std::size_t(i)];
      const float ra = float(c.spheres_[std::size_t(i)].radius + c.padding_) + pair_margin + pair_widen;
      // A sphere clear of b's bounding sphere (or capsule) in every lane still open cannot touch
      // b's spheres.
      const std::uint32_t open = near & ~hit;
      if (!((b.has_capsule ? near_capsule(wa, kb, ra)
                           : lanes::bits(kernels::overlaps(wa, cb, ra + float(b.radius)), wide)) &
            open))
        continue;
      // The same float sums and squares as ra + r_j in scalars, all lanes at once.
      const F rav = lanes::splatf(ra);
      auto touches = [&](int j) __attribute__((always_inline)) {
        const F r = rav + lanes::load(at.spheres[std::size_t(j)].r);
        return kernels::overlaps(wa, s.world[std::size_t(j)], r * r);
      };
      if (wide) {
        for (int j = b.begin; j < b.end; ++j) acc |= touches(j);
        hit = lanes::bits(acc, wide);
      } else {
        for (int j = b.begin; j < b.end; ++j) hit |= lanes::bits(touches(j), wide);
      }
      if ((hit & near) == near) break;
    }
    return hit & near;
  }

  // Every self pair on the lanes still alive. False when no lane is left.
  DMGPLACE_LANE_PASS_INLINE bool self_pairs() {
    const std::size_t nb = c.bodies_.size();
    for (std::size_t pi = 0; pi < c.pairs_.size(); ++pi) {
      if (!alive) return false;
      float pair_widen = widened(nb + pi);
      CapsuleLanes kb{};
      const std::uint32_t near = pair_near(pi, pair_widen, kb);
      if (near) alive &= ~pair_hits(pi, near, pair_widen, kb);
    }
    return true;
  }
};

}  // namespace dmgplace::runtime

#undef DMGPLACE_LANE_PASS_INLINE
