// SphereFieldChecker's environment pass (sphere_check_pass.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/runtime/collision/primitive_obstacles.hpp"
#include "sphere_check_pass.hpp"

namespace dmgplace::runtime {

// Every moving body against the scene: its bounding sphere against the coarse, then the fine grid;
// then sphere by sphere, the exact primitives where the grid cannot tell. In a scene of a few
// primitives (exact_scene()) the same steps read the exact distances instead of the grid, every
// body center at once, then every sphere of a body at once (float lanes: distances_of). Bodies
// left undecided are flagged for the exact layer (with the primitives they may touch, when known).
bool SphereFieldChecker::Pass::environment() {
  const bool exact = c.exact_scene();
  // All body centers first, their fine-grid nodes requested at once (most misses then overlap).
  for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi) {
    s.body_center[bi] = moved(poses[std::size_t(c.bodies_[bi].link)], c.bodies_[bi].center);
    if (!exact && (c.bodies_[bi].moving || c.bodies_[bi].attached)) c.fine_->prefetch(s.body_center[bi]);
  }
  if (exact) body_distances();
  for (std::size_t bi = 0; bi < c.bodies_.size(); ++bi) {
    const Body& b = c.bodies_[bi];
    if (!b.moving && !b.attached) continue;
    if (body_clear(bi, exact)) continue;
    if (!environment_spheres(bi, exact)) return false;
  }
  return true;
}

// Body bi's bounding sphere alone clear of the scene (exact distance, or coarse then fine grid).
bool SphereFieldChecker::Pass::body_clear(std::size_t bi, bool exact) {
  const Body& b = c.bodies_[bi];
  if (exact) {
    const double d = s.body_exact[bi] - b.radius - c.padding_;
    if (d >= 0) {
      cleared(bi, d);
      return true;  // the whole body is clear
    }
  } else if (!outside(s.body_center[bi])) {
    const double dc = c.coarse_lower_bound(s.body_center[bi]) - b.radius - c.padding_;
    if (dc >= 0) {
      cleared(bi, dc);
      return true;  // cleared from the coarse grid alone
    }
    const double d = c.fine_lower_bound(s.body_center[bi]) - b.radius - c.padding_;
    if (d >= 0) {
      cleared(bi, d);
      return true;  // the whole body is clear
    }
  }
  return false;
}

// Body bi's link goes to the exact layer, which certifies it from its exact distance.
void SphereFieldChecker::Pass::flag_environment_link(std::size_t bi) {
  const Body& b = c.bodies_[bi];
  if (certify) {
    mark(bi, kFlagged);
    s.body_clear[bi] = std::numeric_limits<double>::infinity();
  }
  if (b.attached) out.attached_near_env = true;
  else if (out.env_link_count < SphereCheck::kMaxPairs) out.env_links[std::size_t(out.env_link_count++)] = b.link;
  else out.env_overflow = true;
}

// Body bi sphere by sphere: the grid, then the exact primitives where it cannot tell; a sphere
// neither clears flags the body's link for the exact layer. False on a proven collision.
bool SphereFieldChecker::Pass::environment_spheres(std::size_t bi, bool exact) {
  const Body& b = c.bodies_[bi];
  centers(bi);
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
    mark(bi, kBoundsRead);
    for (int i = b.begin; i < b.end; ++i) {
      s.sphere_coarse[std::size_t(i)] = s.sphere_fine[std::size_t(i)] = nan;
      if (!exact) s.sphere_exact[std::size_t(i)] = nan;
    }
  }
  if (exact) exact_distances(bi);
  // An obstacle's surface passes through sphere i's inner ball, inside the link's solid: the
  // field's upper bound at the center proves it, as an exact primitive's distance does below (an
  // inner radius of 0: none known).
  const auto field_proves_collision = [&](int i, const Eigen::Vector3d& w, double fine) {
    return c.inner(i) > 0 && fine < c.inner(i) && c.fine_upper_bound(w) < c.inner(i);
  };
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
      double fine = c.fine_lower_bound(w);
      clearance = fine - sp.radius - c.padding_;
      if (clearance < 0) {  // the cell's corners, before the exact layer: nearly the value at w
        fine = c.fine_cell_lower_bound(w);
        clearance = fine - sp.radius - c.padding_;
      }
      if (certify) s.sphere_fine[std::size_t(i)] = fine;
      if (clearance >= 0) {
        cleared(bi, clearance);
        continue;
      }
      if (field_proves_collision(i, w, fine)) {
        out.environment_free = false;
        out.proven_collision = true;
        return false;
      }
    }
    if (c.obstacles_) {  // exact, inside the grid or not
      // (Exact scenes: a lower bound, at most twice exact_float_error_ below the distance.)
      const double distance = exact ? s.sphere_exact[std::size_t(i)] : c.obstacles_->distance(w);
      if (certify && !exact) s.sphere_exact[std::size_t(i)] = distance;
      const double gap = distance - sp.radius - c.padding_;
      if (gap >= 0) {
        cleared(bi, gap);
        continue;
      }
      const double at_most = exact ? distance + 2.0 * c.exact_float_error_ : distance;
      if (c.inner(i) > 0 && at_most < c.inner(i)) {  // part of the link's solid is inside an obstacle (0: unknown)
        out.environment_free = false;
        out.proven_collision = true;
        return false;
      }
      if (exact) clearance = gap;
    }
    if (!out_of_grid) out.min_clearance = std::min(out.min_clearance, clearance);
    out.environment_free = false;
    out.outside_grid |= out_of_grid && !c.obstacles_;
    if (!flagged) flag_environment_link(bi);
    flagged = true;
    if (!masks) {
      // The link goes to the exact layer anyway, unless one of its other spheres proves the
      // collision first: an exact check costs far more than these reads.
      for (int k = i + 1; k < b.end && !exact; ++k) {
        const Eigen::Vector3d& wk = s.world[std::size_t(k)];
        if (!outside(wk) && field_proves_collision(k, wk, c.fine_lower_bound(wk))) {
          out.proven_collision = true;
          return false;
        }
      }
      break;
    }
    mask |= c.obstacles_->touching(w, sp.radius + c.padding_);
  }
  if (flagged && masks && !out.env_overflow && out.env_links[std::size_t(out.env_link_count - 1)] == b.link)
    out.env_masks[std::size_t(out.env_link_count - 1)] = mask;
  return true;
}

// Lower bounds on the distances of `count` points (`point(k)`) to the scene's primitives, 8 at a
// time in float lanes, into out[k]: the float distance less its rounding bound. A point past
// lane_limit_ (or NaN), where that bound does not hold, is measured in doubles.
template <class Point>
void SphereFieldChecker::Pass::distances_of(int count, Point point, double* out) const {
  constexpr int W = lanes::WF;
  alignas(32) float x[W], y[W], z[W], d[W];
  for (int first = 0; first < count; first += W) {
    const int n = std::min(W, count - first);
    for (int k = 0; k < W; ++k) {  // spare lanes repeat the first point
      const Eigen::Vector3d& w = point(first + (k < n ? k : 0));
      x[k] = float(w.x());
      y[k] = float(w.y());
      z[k] = float(w.z());
    }
    c.obstacles_->distances(x, y, z, d);
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d& w = point(first + k);
      const double limit = c.lane_limit_;
      const bool within = std::abs(w.x()) <= limit && std::abs(w.y()) <= limit && std::abs(w.z()) <= limit;
      out[first + k] = within ? double(d[k]) - c.exact_float_error_ : c.obstacles_->distance(w);
    }
  }
}

void SphereFieldChecker::Pass::exact_distances(std::size_t bi) {
  if (has(bi, kDistances)) return;
  mark(bi, kDistances);
  centers(bi);
  const Body& b = c.bodies_[bi];
  distances_of(
      b.end - b.begin, [&](int k) -> const Eigen::Vector3d& { return s.world[std::size_t(b.begin + k)]; },
      &s.sphere_exact[std::size_t(b.begin)]);
}

void SphereFieldChecker::Pass::body_distances() {
  // Static bodies too: every lane costs the same, and most bodies move.
  s.body_exact.resize(c.bodies_.size());
  distances_of(
      int(c.bodies_.size()), [&](int k) -> const Eigen::Vector3d& { return s.body_center[std::size_t(k)]; },
      s.body_exact.data());
}

}  // namespace dmgplace::runtime
