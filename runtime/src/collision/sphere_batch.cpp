// SphereFieldChecker::free_lanes: the fast layer's "proven free" for 8 configurations at once.
// Forward kinematics runs in SIMD lanes (Kinematics::link_poses_batch); every step after it takes
// one body or sphere across all lanes (centres, grid indices, bounds, exact primitive distances,
// pair distances), so the arithmetic vectorises; only the field loads are one per lane. Compiled for AVX2 + FMA and for
// the portable baseline, chosen at run time (system/simd_dispatch).
#include <array>

#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/system/lanes.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {
namespace {

constexpr int N = PoseBatch::kLanes;
static_assert(N % lanes::W == 0);
struct alignas(64) Xyz {
  double x[N], y[N], z[N];
};

// c = R p + t in every lane (p in registers: as a loop over lanes GCC reloaded it per lane).
inline __attribute__((always_inline)) void transform(const std::array<PoseBatch::Lanes, 12>& T, const Eigen::Vector3d& p, Xyz& c) {
  using lanes::D;
  const D px = lanes::splat(p.x()), py = lanes::splat(p.y()), pz = lanes::splat(p.z());
  for (int h = 0; h < N; h += lanes::W) {
    auto t = [&](int e) __attribute__((always_inline)) { return lanes::load(T[std::size_t(e)].data() + h); };
    lanes::store(c.x + h, t(0) * px + t(1) * py + t(2) * pz + t(9));
    lanes::store(c.y + h, t(3) * px + t(4) * py + t(5) * pz + t(10));
    lanes::store(c.z + h, t(6) * px + t(7) * py + t(8) * pz + t(11));
  }
}

// Lanes whose point p is at least `need` from the scene by the field (inside the grid only): the
// coarse bound where there is one, else the fine one. `alive`: lanes still worth the fine loads.
inline __attribute__((always_inline)) std::uint32_t clear_of_field(const Xyz& p, double need, std::uint32_t alive,
                                                                  const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                                                  const NodeBoundGrid* coarse, const NodeBoundGrid& fine,
                                                                  bool wide) {
  using lanes::D;
  std::uint32_t in_grid = 0;
  for (int h = 0; h < N; h += lanes::W) {
    const D x = lanes::load(p.x + h), y = lanes::load(p.y + h), z = lanes::load(p.z + h);
    in_grid |= lanes::bits((x >= lanes::splat(lo.x())) & (y >= lanes::splat(lo.y())) & (z >= lanes::splat(lo.z())) &
                           (x <= lanes::splat(hi.x())) & (y <= lanes::splat(hi.y())) & (z <= lanes::splat(hi.z())),
                           wide)
               << h;
  }
  alignas(32) double b[N];
  auto at_least_need = [&] {
    std::uint32_t ok = 0;
    for (int h = 0; h < N; h += lanes::W) ok |= lanes::bits(lanes::load(b + h) >= lanes::splat(need), wide) << h;
    return ok;
  };
  std::uint32_t ok = 0;
  if (coarse) {
    coarse->lower_bound_lanes<N>(p.x, p.y, p.z, b);
    ok = at_least_need() & in_grid;
  }
  if ((ok & alive) != (in_grid & alive)) {
    fine.lower_bound_lanes<N>(p.x, p.y, p.z, b);
    ok |= at_least_need();
  }
  return ok & in_grid;
}

// Lanes where spheres a and b (centres in lanes) are closer than `reach` (sum of radii + padding),
// as masks, one per half of the lanes: a caller testing many sphere pairs ORs them and takes the
// bits once (the bits cost more than the test).
static_assert(N == 2 * lanes::W);
inline __attribute__((always_inline)) void add_overlaps(const Xyz& a, const Xyz& b, double reach, lanes::M& lo,
                                                        lanes::M& hi) {
  using lanes::D;
  const D r2 = lanes::splat(reach * reach);
  auto near = [&](int h) __attribute__((always_inline)) -> lanes::M {
    const D dx = lanes::load(a.x + h) - lanes::load(b.x + h), dy = lanes::load(a.y + h) - lanes::load(b.y + h),
            dz = lanes::load(a.z + h) - lanes::load(b.z + h);
    return (lanes::M)(dx * dx + dy * dy + dz * dz < r2);
  };
  lo |= near(0);
  hi |= near(lanes::W);
}
inline __attribute__((always_inline)) std::uint32_t bits(lanes::M lo, lanes::M hi, bool wide) {
  return lanes::bits(lo, wide) | lanes::bits(hi, wide) << lanes::W;
}
inline __attribute__((always_inline)) std::uint32_t overlapping(const Xyz& a, const Xyz& b, double reach, bool wide) {
  lanes::M lo{}, hi{};
  add_overlaps(a, b, reach, lo, hi);
  return bits(lo, hi, wide);
}

}  // namespace

inline __attribute__((always_inline)) std::uint32_t SphereFieldChecker::free_lanes_body(const SphereFieldChecker& c,
                                                                                        const double* const* q, int count,
                                                                                        bool wide) {
  const double* in[N];
  for (int k = 0; k < N; ++k) in[k] = q[k < count ? k : 0];  // idle lanes repeat the first
  thread_local PoseBatch poses;
  c.kin_->link_poses_batch(in, poses);
  const std::uint32_t all = (1u << count) - 1;
  std::uint32_t alive = all;
  thread_local std::vector<Xyz> world, centre;
  thread_local std::vector<char> done;
  world.resize(c.spheres_.size());
  centre.resize(c.bodies_.size());
  done.assign(c.bodies_.size(), 0);
  auto spheres_of = [&](std::size_t bi) {
    if (done[bi]) return;
    const Body& b = c.bodies_[bi];
    const auto& T = poses.pose[std::size_t(b.link)];
    for (int i = b.begin; i < b.end; ++i) transform(T, c.spheres_[std::size_t(i)].center, world[std::size_t(i)]);
    done[bi] = 1;
  };
  // A scene of primitives is tested exactly, in cache: a body's bounding sphere finds the
  // primitives it may reach, its spheres test only those. Otherwise the distance field.
  const PrimitiveObstacles* prims = c.obstacles_.get();
  std::uint64_t reach = ~std::uint64_t(0);
  auto clear_lanes = [&](const Xyz& p, double r, std::uint32_t lanes) __attribute__((always_inline)) {
    if (prims) return prims->clear_lanes<N>(p.x, p.y, p.z, r + c.padding_, lanes, reach, wide);
    return clear_of_field(p, r + c.padding_, lanes, c.lo_, c.hi_, c.coarse_.get(), *c.fine_, wide);
  };
  for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi) {
    const Body& b = c.bodies_[bi];
    transform(poses.pose[std::size_t(b.link)], b.center, centre[bi]);
    if (!b.moving && !b.attached) continue;
    if (prims) reach = prims->reaching_lanes<N>(centre[bi].x, centre[bi].y, centre[bi].z, b.radius + c.padding_, alive, wide);
    std::uint32_t open = alive & ~clear_lanes(centre[bi], b.radius, alive);
    if (!open) continue;
    spheres_of(bi);
    for (int i = b.begin; i < b.end && open; ++i) {
      const std::uint32_t ok = clear_lanes(world[std::size_t(i)], c.spheres_[std::size_t(i)].radius, open);
      alive &= ~(open & ~ok);
      open &= ok;
    }
    if (!alive) return 0;
  }
  for (const Pair& p : c.pairs_) {
    const Xyz &ca = centre[std::size_t(p.a)], &cb = centre[std::size_t(p.b)];
    std::uint32_t near = overlapping(ca, cb, p.reach, wide) & alive;
    if (!near) continue;
    if (p.table >= 0)
      for (int k = 0; k < count; ++k)
        if ((near >> k & 1u) && (*c.tables_)[std::size_t(p.table)].lower_bound(in[k]) - c.padding_ > 0) near &= ~(1u << k);
    if (!near) continue;
    const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
    spheres_of(std::size_t(p.a));
    spheres_of(std::size_t(p.b));
    std::uint32_t hit = 0;
    lanes::M lo{}, hi{};
    for (int i = a.begin; i < a.end; ++i) {
      const Xyz& wa = world[std::size_t(i)];
      const double ra = c.spheres_[std::size_t(i)].radius + c.padding_;
      // A sphere clear of b's bounding sphere in every lane still open cannot touch b's spheres.
      if (!(overlapping(wa, cb, ra + b.radius, wide) & near & ~hit)) continue;
      if (wide) {
        for (int j = b.begin; j < b.end; ++j) add_overlaps(wa, world[std::size_t(j)], ra + c.spheres_[std::size_t(j)].radius, lo, hi);
        hit = bits(lo, hi, wide);
      } else {
        for (int j = b.begin; j < b.end; ++j) hit |= overlapping(wa, world[std::size_t(j)], ra + c.spheres_[std::size_t(j)].radius, wide);
      }
      if ((hit & near) == near) break;
    }
    alive &= ~(hit & near);
    if (!alive) return 0;
  }
  return alive & all;
}

__attribute__((target("avx2,fma"))) std::uint32_t SphereFieldChecker::free_lanes_avx2(const SphereFieldChecker& c,
                                                                                      const double* const* q, int count) {
  return free_lanes_body(c, q, count, true);
}

std::uint32_t SphereFieldChecker::free_lanes_portable(const SphereFieldChecker& c, const double* const* q, int count) {
  return free_lanes_body(c, q, count, false);
}

std::uint32_t SphereFieldChecker::free_lanes(const double* const* q, int count) const {
  if (count <= 0) return 0;
  count = std::min(count, N);
  return simd_path() == SimdPath::Avx2 ? free_lanes_avx2(*this, q, count) : free_lanes_portable(*this, q, count);
}

}  // namespace dmgplace::runtime
