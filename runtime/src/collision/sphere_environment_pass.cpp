// SphereFieldChecker's environment pass (sphere_check_pass.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "sphere_check_pass.hpp"

namespace dmgplace::runtime {

// Every moving body against the scene: its bounding sphere against the coarse, then the fine grid;
// then sphere by sphere, the exact primitives where the grid cannot tell. In a scene of a few
// primitives (exact_scene()) the same steps read the exact distances instead of the grid. Bodies
// left undecided are flagged for the exact layer (with the primitives they may touch, when known).
bool SphereFieldChecker::Pass::environment() {
  const bool exact = c.exact_scene();
  // All body centres first, their fine-grid nodes requested at once (most misses then overlap).
  for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi) {
    s.body_center[bi] = poses[std::size_t(c.bodies_[bi].link)] * c.bodies_[bi].center;
    if (!exact && (c.bodies_[bi].moving || c.bodies_[bi].attached)) c.fine_->prefetch(s.body_center[bi]);
  }
  for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi) {
    const Body& b = c.bodies_[bi];
    if (!b.moving && !b.attached) continue;
    if (exact) {
      const double d = c.obstacles_->distance(s.body_center[bi]) - b.radius - c.padding_;
      if (d >= 0) {
        cleared(bi, d);
        continue;  // the whole body is clear
      }
    } else if (!outside(s.body_center[bi])) {
      const double dc = c.coarse_lower_bound(s.body_center[bi]) - b.radius - c.padding_;
      if (dc >= 0) {
        cleared(bi, dc);
        continue;  // cleared from the coarse grid alone
      }
      const double d = c.fine_lower_bound(s.body_center[bi]) - b.radius - c.padding_;
      if (d >= 0) {
        cleared(bi, d);
        continue;  // the whole body is clear
      }
    }
    centres(bi);
    if (!exact)
      for (int i = b.begin; i < b.end; ++i) c.fine_->prefetch(s.world[std::size_t(i)]);
    // Keep going after a hit: every flagged link is listed, so the exact layer can check just those.
    // With exact primitives every sphere of a flagged link is looked at, to name every primitive
    // the link may touch; without, the first flagged sphere settles the link.
    const bool masks = c.obstacles_ && c.obstacles_->all_have_bits() && !b.attached;
    std::uint64_t mask = 0;
    bool flagged = false;
    // Certified mode keeps what it reads for the certificate's refinement (sphere_coarse ...).
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (certify) {
      s.bounds_done[bi] = 1;
      for (int i = b.begin; i < b.end; ++i) s.sphere_coarse[std::size_t(i)] = s.sphere_fine[std::size_t(i)] = s.sphere_exact[std::size_t(i)] = nan;
    }
    for (int i = b.begin; i < b.end; ++i) {
      const auto& sp = c.spheres_[std::size_t(i)];
      const Eigen::Vector3d& w = s.world[std::size_t(i)];
      // Outside the grid nothing is known: "maybe in collision", for the exact layer to decide.
      // (Band-clamped far cells are fine: clamping only lowers values, which stays conservative.)
      const bool out_of_grid = !exact && outside(w);
      double clearance = -1.0;  // the best bound read (out of the grid: none)
      if (!exact && !out_of_grid) {
        const double bound = c.coarse_lower_bound(w);
        if (certify) s.sphere_coarse[std::size_t(i)] = bound;
        const double coarse = bound - sp.radius - c.padding_;
        if (coarse >= 0) {
          cleared(bi, coarse);
          continue;
        }
        const double fine = c.fine_lower_bound(w);
        if (certify) s.sphere_fine[std::size_t(i)] = fine;
        clearance = fine - sp.radius - c.padding_;
        if (clearance >= 0) {
          cleared(bi, clearance);
          continue;
        }
      }
      if (c.obstacles_) {  // exact, inside the grid or not
        const double distance = c.obstacles_->distance(w);
        if (certify) s.sphere_exact[std::size_t(i)] = distance;
        const double gap = distance - sp.radius - c.padding_;
        if (gap >= 0) {
          cleared(bi, gap);
          continue;
        }
        if (c.inner(i) > 0 && distance < c.inner(i)) {  // part of the link's solid is inside an obstacle (0: unknown)
          out.environment_free = false;
          out.proven_collision = true;
          return false;
        }
        if (exact) clearance = gap;
      }
      if (!out_of_grid) out.min_clearance = std::min(out.min_clearance, clearance);
      out.environment_free = false;
      out.outside_grid |= out_of_grid && !c.obstacles_;
      if (!flagged) {
        flagged = true;
        if (certify) {  // the exact layer certifies this link from its exact distance
          s.body_flagged[bi] = 1;
          s.body_clear[bi] = std::numeric_limits<double>::infinity();
        }
        if (b.attached) out.attached_near_env = true;
        else if (out.env_link_count < SphereCheck::kMaxPairs) out.env_links[std::size_t(out.env_link_count++)] = b.link;
        else out.env_overflow = true;
      }
      if (!masks) break;
      mask |= c.obstacles_->touching(w, sp.radius + c.padding_);
    }
    if (flagged && masks && !out.env_overflow && out.env_links[std::size_t(out.env_link_count - 1)] == b.link)
      out.env_masks[std::size_t(out.env_link_count - 1)] = mask;
  }
  return true;
}

}  // namespace dmgplace::runtime
