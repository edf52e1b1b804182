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
      const double v = speed(c.bodies_[bi].chain);
      if (v > 0) s.cands.push_back({s.body_clear[bi] / v, s.body_clear[bi], bi, false, false, 0, {}});
    }
  const double limit = std::min(table_limit, enough);
  while (!s.cands.empty()) {
    auto it = std::min_element(s.cands.begin(), s.cands.end(), [](const Candidate& x, const Candidate& y) { return x.t < y.t; });
    if (it->t >= limit || it->level == 2) break;
    if (it->level == 0) {
      it->speed = it->pair ? c.pair_speed(it->index, poses, s.body_center, *dir)
                         : c.joint_speed(c.bodies_[it->index].chain, poses, s.body_center[it->index], c.bodies_[it->index].radius, *dir);
      it->t = it->speed.time_to_move(it->clearance);
      it->level = it->fine ? 2 : 1;
      continue;
    }
    // Sphere by sphere (the bounding spheres, or the coarse grid, gave less).
    double clearance = std::numeric_limits<double>::infinity();
    if (it->pair) {
      const Body &a = c.bodies_[std::size_t(c.pairs_[it->index].a)], &b = c.bodies_[std::size_t(c.pairs_[it->index].b)];
      centres(std::size_t(c.pairs_[it->index].a));
      centres(std::size_t(c.pairs_[it->index].b));
      for (int i = a.begin; i < a.end; ++i)
        for (int j = b.begin; j < b.end; ++j)
          clearance = std::min(clearance, (s.world[std::size_t(i)] - s.world[std::size_t(j)]).norm() - c.spheres_[std::size_t(i)].radius -
                                              c.spheres_[std::size_t(j)].radius - c.padding_);
    } else {
      const Body& b = c.bodies_[it->index];
      // The field stops at its band: where it has clamped, the body's whole bounding sphere against
      // the exact primitives (one distance) can prove much more than its spheres against the field.
      if (c.obstacles_ && !it->exact_centre && it->clearance + b.radius + c.padding_ > kBandShare * c.band_) {
        it->exact_centre = true;
        const double e = c.obstacles_->distance(s.body_center[it->index]) - b.radius - c.padding_;
        if (e > it->clearance) {
          it->clearance = e;
          it->t = it->speed.time_to_move(e);
          if (it->t >= limit) continue;
        }
      }
      centres(it->index);
      for (int i = b.begin; i < b.end; ++i) c.fine_->prefetch(s.world[std::size_t(i)]);
      for (int i = b.begin; i < b.end; ++i) {
        const auto& sp = c.spheres_[std::size_t(i)];
        const Eigen::Vector3d& w = s.world[std::size_t(i)];
        double sc = std::max(c.coarse_lower_bound(w), c.fine_lower_bound(w)) - sp.radius - c.padding_;
        // Near a surface the node bound's loss is most of the clearance: ask the exact shapes.
        // So is a sphere the band has clamped (the field then knows only "at least the band").
        if (c.obstacles_ && (sc < kExactBelow || sc + sp.radius + c.padding_ > kBandShare * c.band_))
          sc = std::max(sc, c.obstacles_->distance(w) - sp.radius - c.padding_);
        clearance = std::min(clearance, sc);
      }
    }
    it->clearance = std::max(clearance, it->clearance);
    it->t = it->speed.time_to_move(it->clearance);
    it->level = 2;
  }
  double fd = table_limit;
  for (const auto& k : s.cands) fd = std::min(fd, k.t);
  if (skipped) fd = std::min(fd, enough);
  out.free_distance = std::isfinite(fd) ? fd : 1e9;
}

}  // namespace dmgplace::runtime
