// SphereFieldChecker's certificate pass (sphere_check_pass.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "sphere_check_pass.hpp"

namespace dmgplace::runtime {
namespace {
// Below this field clearance (metres) a refined certificate also asks the exact primitives: the
// node bound's loss is then a large share of the clearance (tried 0.02-0.2 m on MotionBenchMaker).
constexpr double kExactBelow = 0.05;
// A field bound above this share of the band may be the band's clamp, not the distance.
constexpr double kBandShare = 0.75;
}  // namespace

// Every clearance (a body's to the scene, a pair's) is a candidate limit on the certificate, first
// over a cheap static speed (metres per unit of joint motion); the smallest candidates are refined
// until the limit is final or the certificate long enough. Flagged links and pairs are left out:
// the exact layer certifies them (link_time, pair_time).
void SphereFieldChecker::Pass::certificate() {
  for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi)
    if ((c.bodies_[bi].moving || c.bodies_[bi].attached) && std::isfinite(s.body_clear[bi])) {
      const double v = static_speed(bi);
      if (v > 0) candidate(s.body_clear[bi] / v, s.body_clear[bi], bi, false, false);
    }
  const double limit = std::min(table_limit, enough);
  // A candidate lasting `limit` needs no more work: it is set aside and only the smallest such
  // time kept, so the smallest-first scan reads only the candidates still short of it.
  double beyond = std::numeric_limits<double>::infinity();
  double isotropic = std::numeric_limits<double>::infinity();  // the smallest time a directional bound raised
  auto keep = [&](std::size_t at) {                            // after s.times[at] changed
    if (s.times[at] < limit) return;
    beyond = std::min(beyond, s.times[at]);
    s.cands[at] = s.cands.back();
    s.cands.pop_back();
    s.times[at] = s.times.back();
    s.times.pop_back();
  };
  for (std::size_t at = s.cands.size(); at-- > 0;) keep(at);
  while (!s.cands.empty()) {
    const auto at = std::size_t(std::min_element(s.times.begin(), s.times.end()) - s.times.begin());
    Candidate* it = &s.cands[at];
    if (it->level == 2) {
      if (!it->directional) break;
      // Asked only of the smallest candidate: a body another candidate undercuts needs none.
      it->directional = false;
      isotropic = std::min(isotropic, it->t);
      it->t = std::max(it->t, directional_time(*it, limit));
      s.times[at] = it->t;
      keep(at);
      continue;
    }
    if (it->level == 0) {
      it->speed = it->pair ? pair_speed(it->index) : body_speed(it->index);
      it->t = it->speed.time_to_move(it->clearance, limit);
      it->level = it->fine ? 2 : 1;
      s.times[at] = it->t;
      keep(at);
      continue;
    }
    // Sphere by sphere (the bounding spheres, or the coarse grid, gave less).
    double clearance = std::numeric_limits<double>::infinity();
    if (it->pair) {
      clearance = pair_sphere_gap(c.pairs_[it->index]);
    } else {
      const Body& b = c.bodies_[it->index];
      // The field stops at its band: where it has clamped, the body's whole bounding sphere against
      // the exact primitives (one distance) can prove much more than its spheres against the field.
      const bool exact = c.exact_scene();
      if (c.obstacles_ && !exact && !it->exact_center && it->clearance + b.radius + c.padding_ > kBandShare * c.band_) {
        exact_center_bound(*it, limit);
        s.times[at] = it->t;
        if (it->t >= limit) {  // (candidates still listed are short of the limit)
          keep(at);
          continue;
        }
      }
      centers(it->index);
      clearance = exact ? exact_sphere_gaps(it->index) : field_sphere_gaps(*it, limit);
    }
    it->clearance = std::max(clearance, it->clearance);
    it->t = it->speed.time_to_move(it->clearance, limit);
    // Short of the limit near the exact primitives: the body's spheres may be sliding along them
    // (directional_time, once this is the smallest candidate).
    if (!it->pair && c.obstacles_ && it->t < limit) it->directional = true;
    it->level = 2;
    s.times[at] = it->t;
    keep(at);
  }
  double fd = std::min(table_limit, beyond);
  for (const double t : s.times) fd = std::min(fd, t);
  if (skipped) fd = std::min(fd, enough);
  out.free_distance = std::isfinite(fd) ? fd : 1e9;
  out.isotropic_distance = std::min(out.free_distance, isotropic);
}

void SphereFieldChecker::Pass::exact_center_bound(Candidate& k, double limit) {
  const Body& b = c.bodies_[k.index];
  k.exact_center = true;
  const double e = c.obstacles_->distance(s.body_center[k.index]) - b.radius - c.padding_;
  if (e <= k.clearance) return;
  k.clearance = e;
  k.t = k.speed.time_to_move(e, limit);
}

// The smallest gap between a pair's spheres. A root only where it can lower the minimum:
// |wa - wb| - r < clearance, squared.
double SphereFieldChecker::Pass::pair_sphere_gap(const Pair& p) {
  const Body &a = c.bodies_[std::size_t(p.a)], &b = c.bodies_[std::size_t(p.b)];
  centers(std::size_t(p.a));
  centers(std::size_t(p.b));
  double clearance = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d& cb = s.body_center[std::size_t(p.b)];
  for (int i = a.begin; i < a.end; ++i) {
    const Eigen::Vector3d& wa = s.world[std::size_t(i)];
    const double ra = c.spheres_[std::size_t(i)].radius + c.padding_;
    const double row = ra + b.radius + clearance;  // past b's bounding sphere by the minimum: no sphere of b is nearer
    if (row > 0 && (wa - cb).squaredNorm() >= row * row) continue;
    for (int j = b.begin; j < b.end; ++j) {
      const double r = ra + c.spheres_[std::size_t(j)].radius, reach = r + clearance;
      const double d2 = (wa - s.world[std::size_t(j)]).squaredNorm();
      if (reach > 0 && d2 >= reach * reach) continue;
      clearance = std::min(clearance, std::sqrt(d2) - r);
    }
  }
  return clearance;
}

// A body's spheres' gaps to the scene (into s.sphere_gap, for directional_time), the smallest
// returned. What the environment pass read for them is not read again (NaN: not read there).
double SphereFieldChecker::Pass::exact_sphere_gaps(std::size_t bi) {
  const Body& b = c.bodies_[bi];
  double clearance = std::numeric_limits<double>::infinity();
  for (int i = b.begin; i < b.end; ++i) {
    s.sphere_gap[std::size_t(i)] = exact_distance(bi, i) - c.spheres_[std::size_t(i)].radius - c.padding_;
    clearance = std::min(clearance, s.sphere_gap[std::size_t(i)]);
  }
  return clearance;
}

double SphereFieldChecker::Pass::exact_distance(std::size_t bi, int i) {
  if (c.exact_scene()) {
    exact_distances(bi);
    return s.sphere_exact[std::size_t(i)];
  }
  const double read = has(bi, kBoundsRead) ? s.sphere_exact[std::size_t(i)] : std::numeric_limits<double>::quiet_NaN();
  return std::isnan(read) ? c.obstacles_->distance(s.world[std::size_t(i)]) : read;
}

// The same from the field's bounds, the exact primitives asked only where those fall short.
double SphereFieldChecker::Pass::field_sphere_gaps(const Candidate& cand, double limit) {
  const Body& b = c.bodies_[cand.index];
  const bool known = has(cand.index, kBoundsRead);
  double clearance = std::numeric_limits<double>::infinity();
  for (int i = b.begin; i < b.end; ++i)
    if (!known || std::isnan(s.sphere_fine[std::size_t(i)])) c.fine_->prefetch(s.world[std::size_t(i)]);
  // Field bounds first. Near a surface the node bound's loss is most of the clearance, so the
  // exact shapes are asked there; so they are where the band has clamped (the field then knows
  // only "at least the band"). An exact distance only raises a sphere's bound, so it is asked
  // only while the field's bound is below the smallest clearance so far, smallest first.
  s.exact_order.clear();
  for (int i = b.begin; i < b.end; ++i) {
    const auto& sp = c.spheres_[std::size_t(i)];
    const Eigen::Vector3d& w = s.world[std::size_t(i)];
    const double co = known && !std::isnan(s.sphere_coarse[std::size_t(i)]) ? s.sphere_coarse[std::size_t(i)]
                                                                            : c.coarse_lower_bound(w);
    const double fi =
        known && !std::isnan(s.sphere_fine[std::size_t(i)]) ? s.sphere_fine[std::size_t(i)] : c.fine_lower_bound(w);
    const double sc = std::max(co, fi) - sp.radius - c.padding_;
    s.sphere_gap[std::size_t(i)] = sc;
    if (c.obstacles_ && (sc < kExactBelow || sc + sp.radius + c.padding_ > kBandShare * c.band_))
      s.exact_order.push_back({sc, i});
    else clearance = std::min(clearance, sc);
  }
  std::sort(s.exact_order.begin(), s.exact_order.end());
  // A clearance lasting `limit` is all the caller needs (clearance_for): past it the field's
  // bounds will do. Should the time still fall short, the rest of the spheres are asked too.
  double need = cand.speed.clearance_for(limit);
  for (std::size_t k = 0; k < s.exact_order.size();) {
    const auto [sc, i] = s.exact_order[k];
    if (sc >= std::min(clearance, need)) {  // neither this sphere nor the rest can lower it below that
      if (sc >= clearance || !(cand.speed.time_to_move(sc, limit) < limit)) {
        clearance = std::min(clearance, sc);
        break;
      }
      need = std::numeric_limits<double>::infinity();  // fell short: the rest exactly
    }
    s.sphere_gap[std::size_t(i)] =
        std::max(sc, exact_distance(cand.index, i) - c.spheres_[std::size_t(i)].radius - c.padding_);
    clearance = std::min(clearance, s.sphere_gap[std::size_t(i)]);
    ++k;
  }
  return clearance;
}

// How long a body's spheres keep clear of the scene's primitives, each sphere and primitive
// closing their gap only as fast as the sphere moves along their separating direction
// (displacement_bound.hpp, directional): a body sliding along a shelf lasts longer than its
// clearance over its speed. Only primitives nearer than the body's displacement bound are asked.
double SphereFieldChecker::Pass::directional_time(const Candidate& cand, double limit) {
  const Body& b = c.bodies_[cand.index];
  BallVelocity velocity;
  body_speed(cand.index, &velocity);
  // A gap wider than the body's displacement bound over t (in any direction) cannot end before t:
  // only gaps narrower than `reach` are worth a directional time.
  double t = limit, reach = cand.speed.displacement(limit);
  thread_local std::vector<int> prims;
  thread_local std::vector<PrimitiveObstacles::Separation> near;
  c.obstacles_->reaching(s.body_center[cand.index], reach + b.radius + c.padding_, prims);
  for (int i = b.begin; i < b.end && t > 0 && !prims.empty(); ++i) {
    if (s.sphere_gap[std::size_t(i)] >= reach) continue;  // every gap of this sphere is at least that
    const Eigen::Vector3d& w = s.world[std::size_t(i)];
    const double r = c.spheres_[std::size_t(i)].radius + c.padding_;
    if (!c.obstacles_->separations(w, reach + r, prims, near)) return 0.0;
    for (const auto& sep : near) {
      const double gap = sep.distance - r;
      if (!(gap > 0)) return 0.0;
      if (gap >= reach) continue;
      // Only the smallest time counts: past t, time_to_move may stop at its cheap bounds.
      const double tk = cand.speed.along(velocity.along(sep.normal, w, r)).time_to_move(gap, t);
      if (tk < t) {
        t = tk;
        reach = cand.speed.displacement(t);
      }
    }
  }
  return t;
}

void SphereFieldChecker::Pass::levers(std::size_t bi) {
  if (has(bi, kLevers)) return;
  mark(bi, kLevers);
  const Body& b = c.bodies_[bi];
  for (std::size_t k = 0; k < b.chain.size(); ++k) {
    const ChainJoint& j = b.chain[k];
    const auto slot = std::size_t(j.slot);
    if (!s.slot_done[slot]) {
      const Eigen::Isometry3d& T = poses[std::size_t(j.child)];
      s.slot_axis[slot] = T.linear() * j.axis;
      s.slot_origin[slot] = T.translation();
      s.slot_done[slot] = 1;
    }
    if (j.prismatic) continue;
    const auto e = std::size_t(b.lever_begin) + k;
    s.lever[e] = s.slot_axis[slot].cross(s.body_center[bi] - s.slot_origin[slot]);
    s.lever_norm[e] = s.lever[e].norm();
  }
}

DisplacementBound SphereFieldChecker::Pass::ball_speed(std::size_t bi, const std::vector<ChainJoint>& joints,
                                                       const int* at, BallVelocity* velocity) {
  levers(bi);
  const Body& b = c.bodies_[bi];
  BallMotion m(s.body_center[bi], b.radius);
  for (int k = int(joints.size()) - 1; k >= 0; --k) {  // from the top of the chain down
    const ChainJoint& j = joints[std::size_t(k)];
    const double rate = (*dir)[j.slot];
    if (j.prismatic) {
      m.add_prismatic(s.slot_axis[std::size_t(j.slot)], rate, j.reach);
      continue;
    }
    const auto e = std::size_t(b.lever_begin + (at ? at[k] : k));
    m.add_revolute_arm(s.slot_axis[std::size_t(j.slot)], s.lever[e], s.lever_norm[e], rate, j.reach);
  }
  if (velocity) *velocity = m.velocity();
  return m.bound();
}

}  // namespace dmgplace::runtime
