#pragma once
// The checker IK, the sampler and the planner use: the fast sphere layer answers "free" on its own
// (it is conservative), and only its "maybe" is sent to the exact FCL layer.
#include <atomic>
#include <limits>
#include <memory>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"

namespace dmgplace::runtime {

struct CheckCounters {
  std::atomic<long> fast{0};         // every query
  std::atomic<long> exact_pairs{0};  // settled by exact checks of the flagged links and pairs only
  std::atomic<long> exact_full{0};   // needed the full exact check
  std::atomic<long> proven_collisions{0};  // settled as colliding by the spheres' inner balls
};

class TwoLayerChecker {
 public:
  TwoLayerChecker(SphereFieldChecker fast, ExactChecker exact, std::shared_ptr<CheckCounters> counters = nullptr)
      : fast_(std::move(fast)), exact_(std::move(exact)),
        counters_(counters ? std::move(counters) : std::make_shared<CheckCounters>()) {
    // Both layers read one set of link poses per query: they must pose the same robot.
    if (&fast_.kinematics() != &exact_.kinematics())
      throw Error("TwoLayerChecker", "layers", "the fast and exact layers use different kinematics");
  }

  // One forward kinematics per query, shared by both layers.
  bool is_free(const Eigen::VectorXd& q) const {
    const auto& poses = poses_at(q);
    return settle(q, poses, fast_.check(q, poses));
  }
  // < 0: q collides; otherwise q is free and so is q + t * direction for t in [0, result]
  // (0 when the exact layer had to decide, which certifies nothing beyond q). `enough`: the
  // longest certificate the caller can use.
  double free_distance(const Eigen::VectorXd& q, const Eigen::VectorXd& direction,
                       double enough = std::numeric_limits<double>::infinity()) const {
    const auto& poses = poses_at(q);
    const SphereCheck f = fast_.check_along(q, poses, direction, enough);
    if (!settle(q, poses, f)) return -1.0;
    return f.free() ? f.free_distance : 0.0;
  }
  // Which of q[0..count) (count <= 8) the fast layer alone proves free, in one SIMD pass
  // (SphereFieldChecker::free_lanes); unset bits are undecided, for is_free or free_distance.
  std::uint32_t proven_free(const double* const* q, int count) const {
    counters_->fast += count;
    return fast_.free_lanes(q, count);
  }
  const SphereFieldChecker& fast() const { return fast_; }
  const ExactChecker& exact() const { return exact_; }
  const CheckCounters& counters() const { return *counters_; }

 private:
  const std::vector<Eigen::Isometry3d>& poses_at(const Eigen::VectorXd& q) const {
    thread_local std::vector<Eigen::Isometry3d> poses;
    exact_.kinematics().link_poses(q, poses);
    return poses;
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
      ++counters_->exact_pairs;
      return exact_.links_environment_free(poses, f.env_links.data(), f.env_link_count, f.attached_near_env, f.env_masks.data()) &&
             exact_.link_pairs_free(poses, f.pairs.data(), f.pair_count);
    }
    ++counters_->exact_full;
    return exact_.is_free(q);
  }
  SphereFieldChecker fast_;
  ExactChecker exact_;
  std::shared_ptr<CheckCounters> counters_;
};

}  // namespace dmgplace::runtime
