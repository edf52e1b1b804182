#pragma once
// The checker IK, the sampler and the planner use: the fast sphere layer answers "free" on its own
// (it is conservative), and only its "maybe" is sent to the exact FCL layer.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"

namespace dmgplace::runtime {

struct CheckCounters {
  std::atomic<long> fast{0};               // every query
  std::atomic<long> exact_pairs{0};        // settled by exact checks of the flagged links and pairs only
  std::atomic<long> exact_full{0};         // needed the full exact check
  std::atomic<long> proven_collisions{0};  // settled as colliding by the spheres' inner balls
  std::atomic<long> exact_gaps{
      0};  // flagged links and pairs all settled (and certified, when asked) by exact clearances
};

class TwoLayerChecker {
 public:
  TwoLayerChecker(SphereFieldChecker fast, ExactChecker exact, std::shared_ptr<CheckCounters> counters = nullptr)
      : fast_(std::move(fast)), exact_(std::move(exact)),
        counters_(counters ? std::move(counters) : std::make_shared<CheckCounters>()) {
    // Both layers read one set of link poses per query: they must pose the same robot.
    if (&fast_.kinematics() != &exact_.kinematics())
      throw Error("TwoLayerChecker", "layers", "the fast and exact layers use different kinematics");
    gaps_ = exact_.gaps_are_cheap();
    mesh_links_ = exact_.links_have_meshes();
  }

  // One forward kinematics per query, shared by both layers.
  bool is_free(const Eigen::VectorXd& q) const {
    const auto& poses = poses_at(q);
    return settle(q, poses, fast_.check(q, poses));
  }
  // < 0: q collides; otherwise q is free and so is q + t * direction for t in [0, result].
  // `enough`: the longest certificate the caller can use. Where the spheres flag links (near the
  // scene, or a pair close) and exact gaps are cheap (robot and scene all primitives), the links'
  // exact clearances certify them (exact_gaps): the certificate is the smallest of theirs and the
  // spheres' for the rest. Otherwise (link meshes, touching, a held object, a mesh scene) the
  // exact layer's yes/no decides and certifies nothing beyond q (0).
  // `isotropic` (optional): the same certificate without directional bounds (SphereCheck::
  // isotropic_distance), a guide to how far lane checks reach here.
  double free_distance(const Eigen::VectorXd& q, const Eigen::VectorXd& direction,
                       double enough = std::numeric_limits<double>::infinity(), double* isotropic = nullptr) const {
    const auto& poses = poses_at(q);
    const SphereCheck f = fast_.check_along(q, poses, direction, enough);
    double iso = 0;
    double fd = 0;
    if (f.free()) {
      ++counters_->fast;
      fd = f.free_distance;
      iso = f.isotropic_distance;
    } else if (const double t =
                   gaps_ && enough > 0 && !f.proven_collision ? exact_gaps(poses, f, direction, enough, iso) : 0.0;
               t > 0) {
      ++counters_->fast;
      ++counters_->exact_gaps;
      fd = std::min(t, f.free_distance);
      iso = std::min(iso, f.isotropic_distance);
    } else {
      fd = iso = settle(q, poses, f) ? 0.0 : -1.0;
    }
    if (isotropic) *isotropic = std::min(iso, fd);
    return fd;
  }
  // Which of q[0..count) (count <= 8) the fast layer alone proves free, in one SIMD pass
  // (SphereFieldChecker::free_lanes); unset bits are undecided, for is_free or free_distance.
  std::uint32_t proven_free(const double* const* q, int count) const {
    counters_->fast += count;
    return fast_.free_lanes(q, count);
  }
  // The same, each bit proving every configuration within `reach` of q[k] along +-direction
  // (SphereFieldChecker::free_lanes_along).
  std::uint32_t proven_free_along(const double* const* q, int count, const Eigen::VectorXd& direction,
                                  double reach) const {
    counters_->fast += count;
    return fast_.free_lanes_along(q, count, direction, reach);
  }
  const SphereFieldChecker& fast() const { return fast_; }
  // Exact gaps on or off (on by default exactly when they are cheap): tests and benchmarks.
  void set_exact_gaps(bool on) { gaps_ = on; }
  const ExactChecker& exact() const { return exact_; }
  const CheckCounters& counters() const { return *counters_; }

 private:
  const std::vector<Eigen::Isometry3d>& poses_at(const Eigen::VectorXd& q) const {
    thread_local std::vector<Eigen::Isometry3d> poses;
    exact_.kinematics().link_poses(q, poses);
    return poses;
  }
  // How long the flagged links and pairs of `f` keep their exact clearances along `direction`;
  // 0 when one cannot be had (the caller then decides by the exact yes/no). Each gap is proven
  // only as far as lasting `enough` needs (clearance_for: GJK stops there); should the time still
  // fall short of `enough`, the full gap.
  double exact_gaps(const std::vector<Eigen::Isometry3d>& poses, const SphereCheck& f, const Eigen::VectorXd& direction,
                    double enough, double& isotropic) const {
    isotropic = 0;
    if (f.env_overflow || f.pairs_overflow || f.attached_involved || f.attached_near_env || f.outside_grid) return 0.0;
    auto lasts = [&](const DisplacementBound& v, auto gap_up_to) {
      const double need = v.clearance_for(enough);
      const double gap = gap_up_to(need);
      if (!(gap > 0)) return 0.0;
      const double t = v.time_to_move(gap, enough);
      return t < enough && gap >= need ? v.time_to_move(gap_up_to(std::numeric_limits<double>::infinity())) : t;
    };
    double t = std::numeric_limits<double>::infinity(), iso = t;
    DisplacementBound v;
    BallVelocity velocity;
    for (int k = 0; k < f.env_link_count && t > 0; ++k) {
      const int link = f.env_links[std::size_t(k)];
      if (!fast_.link_speed(poses, link, direction, v, &velocity)) return 0.0;
      // Each scene shape's gap closes only as fast as the link moves along their separating
      // direction (displacement_bound.hpp, directional): sliding past a shape lasts longer.
      double nearest = std::numeric_limits<double>::infinity();
      t = std::min(t, exact_.link_environment_time(
                          poses, link, v.clearance_for(enough), enough,
                          [&](double gap, const Eigen::Vector3d& n) {
                            nearest = std::min(nearest, gap);
                            return (n.squaredNorm() < 0.5 ? v : v.along(velocity.along(n))).time_to_move(gap, enough);
                          },
                          [&](double time) { return v.displacement(time); }));
      iso = std::min(iso, v.time_to_move(nearest, enough));
    }
    for (int k = 0; k < f.pair_count && t > 0; ++k) {
      const auto [a, b] = f.pairs[std::size_t(k)];
      if (!fast_.pair_speed(poses, a, b, direction, v)) return 0.0;
      t = std::min(t, lasts(v, [&](double need) { return exact_.link_pair_gap(poses, a, b, need); }));
    }
    if (!std::isfinite(t)) return 0.0;
    isotropic = std::min(iso, t);
    return t;
  }
  bool settle(const Eigen::VectorXd& q, const std::vector<Eigen::Isometry3d>& poses, const SphereCheck& f) const {
    ++counters_->fast;
    if (f.free()) return true;
    if (f.proven_collision) {
      ++counters_->proven_collisions;
      return false;
    }
    // Only what the spheres flagged goes to FCL: those links against the scene, those link pairs
    // against each other. Overflows and held-object self pairs take the full check.
    if (!f.env_overflow && !f.pairs_overflow && !f.attached_involved) {
      // Where exact gaps are cheap, a flagged link or pair with a proven clearance is free: only
      // the others go to FCL (a hull's gap costs a fraction of FCL's mesh test). Only the sign is
      // asked: GJK stops at the first separating bound.
      std::array<int, SphereCheck::kMaxPairs> links;
      std::array<std::uint64_t, SphereCheck::kMaxPairs> masks;
      std::array<std::pair<int, int>, SphereCheck::kMaxPairs> pairs;
      int nl = 0, np = 0;
      // With the held object near the scene FCL runs anyway: gaps then only spare it link meshes.
      const bool gaps = gaps_ && !f.outside_grid && (!f.attached_near_env || mesh_links_);
      for (int k = 0; k < f.env_link_count; ++k)
        if (!gaps || !(exact_.link_environment_gap(poses, f.env_links[std::size_t(k)], 0.0) > 0)) {
          links[std::size_t(nl)] = f.env_links[std::size_t(k)];
          masks[std::size_t(nl++)] = f.env_masks[std::size_t(k)];
        }
      for (int k = 0; k < f.pair_count; ++k) {
        const auto [a, b] = f.pairs[std::size_t(k)];
        if (!gaps || !(exact_.link_pair_gap(poses, a, b, 0.0) > 0)) pairs[std::size_t(np++)] = f.pairs[std::size_t(k)];
      }
      if (nl == 0 && np == 0 && !f.attached_near_env) {
        ++counters_->exact_gaps;
        return true;
      }
      ++counters_->exact_pairs;
      return exact_.links_environment_free(poses, links.data(), nl, f.attached_near_env, masks.data()) &&
             exact_.link_pairs_free(poses, pairs.data(), np);
    }
    ++counters_->exact_full;
    return exact_.is_free(q);
  }
  SphereFieldChecker fast_;
  ExactChecker exact_;
  bool gaps_ = false;        // exact_gaps is worth asking (gaps_are_cheap)
  bool mesh_links_ = false;  // links_have_meshes
  std::shared_ptr<CheckCounters> counters_;
};

}  // namespace dmgplace::runtime
