#pragma once
// The checker IK, the sampler and the planner use: the fast sphere layer answers "free" on its own
// (it is conservative), and only its "maybe" is sent to the exact FCL layer.
#include <atomic>
#include <limits>
#include <memory>

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
        counters_(counters ? std::move(counters) : std::make_shared<CheckCounters>()) {}

  bool is_free(const Eigen::VectorXd& q) const { return settle(q, fast_.check(q)); }
  // < 0: q collides; otherwise q is free and so is q + t * direction for t in [0, result]
  // (0 when the exact layer had to decide, which certifies nothing beyond q). `enough`: the
  // longest certificate the caller can use.
  double free_distance(const Eigen::VectorXd& q, const Eigen::VectorXd& direction,
                       double enough = std::numeric_limits<double>::infinity()) const {
    const SphereCheck f = fast_.check_along(q, direction, enough);
    if (!settle(q, f)) return -1.0;
    return f.free() ? f.free_distance : 0.0;
  }
  const SphereFieldChecker& fast() const { return fast_; }
  const ExactChecker& exact() const { return exact_; }
  const CheckCounters& counters() const { return *counters_; }

 private:
  bool settle(const Eigen::VectorXd& q, const SphereCheck& f) const {
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
      return exact_.links_environment_free(q, f.env_links.data(), f.env_link_count, f.attached_near_env, f.env_masks.data()) &&
             exact_.link_pairs_free(q, f.pairs.data(), f.pair_count);
    }
    ++counters_->exact_full;
    return exact_.is_free(q);
  }
  SphereFieldChecker fast_;
  ExactChecker exact_;
  std::shared_ptr<CheckCounters> counters_;
};

}  // namespace dmgplace::runtime
