// SphereFieldChecker::pair_contact: a body pair's sphere-by-sphere test for the scalar passes, in
// doubles four spheres at a time, each body's spheres in its own link frame (pair_spheres_). b's
// bounding-sphere center goes into a's frame once, and each of a's spheres near it into b's frame:
// no sphere is moved into the world, where the world-frame loop moved every sphere of both bodies
// for a pair that mostly needs one or two of a's (docs/perf-log.md has what it saved). Compiled for AVX2 and for the portable baseline, chosen at run time (system/simd_dispatch).
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/system/lanes.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {

template <bool Wide>
inline __attribute__((always_inline)) SphereFieldChecker::PairContact SphereFieldChecker::pair_contact_body(
    const SphereFieldChecker& c, const Pair& p, const Eigen::Isometry3d& Ta, const Eigen::Isometry3d& Tb,
    const Eigen::Vector3d& cb) {
  using lanes::D;
  using lanes::splat;
  const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
  const int wa = local_width(a), wb = local_width(b);
  const double* la = c.pair_spheres_.data() + a.local;
  const double* lb = c.pair_spheres_.data() + b.local;
  // b's bounding sphere in a's frame: a's spheres clear of it cannot touch b's spheres.
  const Eigen::Vector3d cba = Ta.linear().transpose() * (cb - Ta.translation());
  const D cx = splat(cba.x()), cy = splat(cba.y()), cz = splat(cba.z());
  const D reach_b = splat(c.padding_ + b.radius);
  // a's frame into b's, made at a's first sphere near b.
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  bool relative = false;
  for (int g = 0; g < wa; g += lanes::W) {
    const D dx = lanes::load(la + g) - cx, dy = lanes::load(la + wa + g) - cy, dz = lanes::load(la + 2 * wa + g) - cz;
    const D rab = lanes::load(la + 3 * wa + g) + reach_b;
    for (std::uint32_t near = lanes::bits((lanes::M)(dx * dx + dy * dy + dz * dz < rab * rab), Wide); near;
         near &= near - 1) {
      const int i = g + __builtin_ctz(near);
      if (!relative) {
        R.noalias() = Tb.linear().transpose() * Ta.linear();
        t.noalias() = Tb.linear().transpose() * (Ta.translation() - Tb.translation());
        relative = true;
      }
      const Eigen::Vector3d q = R * Eigen::Vector3d(la[i], la[wa + i], la[2 * wa + i]) + t;
      const D qx = splat(q.x()), qy = splat(q.y()), qz = splat(q.z());
      const D ra = splat(la[3 * wa + i] + c.padding_);
      for (int h = 0; h < wb; h += lanes::W) {
        const D ex = lanes::load(lb + h) - qx, ey = lanes::load(lb + wb + h) - qy,
                ez = lanes::load(lb + 2 * wb + h) - qz;
        const D r = ra + lanes::load(lb + 3 * wb + h);
        const D s2 = ex * ex + ey * ey + ez * ez;
        if (const std::uint32_t hit = lanes::bits((lanes::M)(s2 < r * r), Wide)) {
          const int j = h + __builtin_ctz(hit);
          return {a.begin + i, b.begin + j, s2[j - h]};
        }
      }
    }
  }
  return {};
}

__attribute__((target("avx2"), flatten)) SphereFieldChecker::PairContact SphereFieldChecker::pair_contact_avx2(
    const SphereFieldChecker& c, const Pair& p, const Eigen::Isometry3d& Ta, const Eigen::Isometry3d& Tb,
    const Eigen::Vector3d& cb) {
  return pair_contact_body<true>(c, p, Ta, Tb, cb);
}

SphereFieldChecker::PairContact SphereFieldChecker::pair_contact(const Pair& p, const Eigen::Isometry3d& Ta,
                                                                 const Eigen::Isometry3d& Tb,
                                                                 const Eigen::Vector3d& cb) const {
  return simd_path() == SimdPath::Avx2 ? pair_contact_avx2(*this, p, Ta, Tb, cb)
                                       : pair_contact_body<false>(*this, p, Ta, Tb, cb);
}

}  // namespace dmgplace::runtime
