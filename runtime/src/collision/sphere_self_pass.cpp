// SphereFieldChecker's self-pair pass (sphere_check_pass.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "sphere_check_pass.hpp"

namespace dmgplace::runtime {

// Every checked body pair: bounding spheres, then the pair's self-distance table, then sphere by
// sphere (two inner balls overlapping prove a collision). Overlapping pairs are flagged for the
// exact layer; in certified mode each gap becomes a candidate limit on the certificate.
bool SphereFieldChecker::Pass::self_pairs() {
  // A clearance lasting past `enough` is not looked at closely (most pairs cost no sqrt): it only
  // proves `enough`, which caps the certificate.
  for (std::size_t pi = 0; pi < c.pairs_.size(); ++pi) {
    const Pair& p = c.pairs_[pi];
    const double rb = p.reach;
    const double d2 = (s.body_center[std::size_t(p.a)] - s.body_center[std::size_t(p.b)]).squaredNorm();
    const double v = certify ? static_speed(c.bodies_.size() + pi) : 0.0;
    const bool certify_this = v > 0;  // (a pair the motion does not move relative needs nothing)
    const double need = certify_this ? enough * v : 0.0;
    if (d2 >= rb * rb) {
      if (certify_this) {
        if (d2 < (rb + need) * (rb + need)) {
          const double gap = std::sqrt(d2) - rb;
          candidate(gap / v, gap, pi, true, false);
        } else {
          skipped = true;
        }
      }
      continue;
    }
    const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
    if (p.table >= 0) {
      const Table& t = (*c.tables_)[std::size_t(p.table)];
      const double lb = t.lower_bound(*q) - c.padding_;
      if (lb > 0) {
        if (certify_this) {
          // Only the table's joints move the pair relative to each other, at most `slope` each.
          const double vt = t.speed(dir->data());
          if (vt > 0) table_limit = std::min(table_limit, lb / vt);
        }
        continue;
      }
    }
    if (!certify_this) {
      // No gaps to measure: the first overlap decides, in the bodies' own frames.
      const PairContact k =
          c.pair_contact(p, poses[std::size_t(a.link)], poses[std::size_t(b.link)], s.body_center[std::size_t(p.b)]);
      if (k.i < 0) continue;
      if (proven_overlap(k.i, k.j, k.s2)) return false;
      flag(a, b);
      if (out.pairs_overflow) return false;
      continue;
    }
    double gap = std::numeric_limits<double>::infinity();
    bool beyond = false;
    const PairSpheres found = pair_spheres(p, need, gap, beyond);
    if (found == PairSpheres::ProvenCollision) return false;
    if (found == PairSpheres::Apart) {
      if (std::isfinite(gap)) candidate(gap / v, gap, pi, true, true);
      else skipped |= beyond;
      continue;
    }
    flag(a, b);
    if (out.pairs_overflow) return false;
  }
  return true;
}

// A pair's spheres in the world, for a certificate: the smallest gap found up to `need` (gap), or
// a touching sphere pair. The pair's gap so far: a sphere pair past it cannot lower it, and all
// share the pair's speed bound, so such pairs need no root. Past `need`, unexamined, they only
// cap the certificate (beyond), and only when no gap is found at all (a finite gap limits it more).
SphereFieldChecker::Pass::PairSpheres SphereFieldChecker::Pass::pair_spheres(const Pair& p, double need, double& gap,
                                                                             bool& beyond) {
  const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
  centers(std::size_t(p.a));
  centers(std::size_t(p.b));
  const Eigen::Vector3d& cb = s.body_center[std::size_t(p.b)];
  for (int i = a.begin; i < a.end; ++i) {
    const Eigen::Vector3d& wa = s.world[std::size_t(i)];
    const double ra = c.spheres_[std::size_t(i)].radius + c.padding_;
    const double look = std::min(gap, need);
    // Past b's bounding sphere by `look`, this sphere is past each of b's spheres by as much.
    const double rab = ra + b.radius + look;
    if ((wa - cb).squaredNorm() >= rab * rab) {
      beyond = true;
      continue;
    }
    for (int j = b.begin; j < b.end; ++j) {
      const double r = ra + c.spheres_[std::size_t(j)].radius;
      const double s2 = (wa - s.world[std::size_t(j)]).squaredNorm();
      if (s2 < r * r) return proven_overlap(i, j, s2) ? PairSpheres::ProvenCollision : PairSpheres::Touching;
      const double reach = r + std::min(gap, need);
      if (s2 < reach * reach) gap = std::min(gap, std::sqrt(s2) - r);
      else beyond = true;
    }
  }
  return PairSpheres::Apart;
}

bool SphereFieldChecker::Pass::proven_overlap(int i, int j, double s2) {
  // The two inner balls overlap: so do the solids (both must have a ball: 0 is unknown).
  const double ia = c.inner(i), ib = c.inner(j), in = ia + ib;
  if (!(ia > 0 && ib > 0 && s2 < in * in)) return false;
  out.self_free = false;
  out.proven_collision = true;
  return true;
}

void SphereFieldChecker::Pass::flag(const Body& a, const Body& b) {
  out.self_free = false;
  if (a.attached || b.attached) out.attached_involved = true;
  if (out.pair_count == SphereCheck::kMaxPairs) {
    out.pairs_overflow = true;
    return;
  }
  out.pairs[std::size_t(out.pair_count++)] = {a.link, b.link};
}

}  // namespace dmgplace::runtime
