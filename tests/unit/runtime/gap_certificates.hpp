#pragma once
// Shared by the built-in arm's and the Panda's tests: TwoLayerChecker::free_distance on random
// states and directions. A collision is never certified; a state the spheres flagged but exact
// clearances certified keeps every state of its certificate (both ways, 1 mm steps or finer) free
// for FCL, and a certificate asked for less is at least that long and no longer than the full
// one. Returns how many such certificates were walked.
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/runtime/collision/two_layer_checker.hpp"

namespace dmgplace::test {

inline int walk_gap_certificates(const runtime::TwoLayerChecker& both, const runtime::ExactChecker& exact, int states,
                                 std::uint64_t seed, double* longest) {
  const runtime::Kinematics& kin = exact.kinematics();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  int walked = 0;
  *longest = 0;
  for (int i = 0; i < states; ++i) {
    Eigen::VectorXd q(kin.dof()), dir(kin.dof());
    for (int j = 0; j < kin.dof(); ++j) {
      q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
      dir[j] = g(rng);
    }
    dir.normalize();
    const long gaps_before = both.counters().exact_gaps.load();
    const double t = both.free_distance(q, dir, 1.0);
    const bool free = exact.is_free(q);
    EXPECT_EQ(t >= 0, free) << "q = " << q.transpose();
    if (both.counters().exact_gaps.load() == gaps_before || t <= 0) continue;
    // Asked for less, the gaps are proven only that far: at least what was asked (or all there
    // is), never more than the full answer. Up to GJK's tolerance: each gap is a bound within
    // 1e-5 m of the distance, from wherever the thread's last query of the same solids ended
    // (GapHint), so two queries' gaps may differ by that, and their certificates by that over
    // the links' speeds.
    const double all = both.free_distance(q, dir), enough = 0.05 * u(rng);
    const double limited = both.free_distance(q, dir, enough);
    const double gjk = 2e-4;
    EXPECT_GE(limited, std::min(enough, all) - gjk) << "q = " << q.transpose();
    EXPECT_LE(limited, all + gjk) << "q = " << q.transpose();
    ++walked;
    *longest = std::max(*longest, t);
    const double step = std::min(0.001, t / 20);
    for (const double sign : {1.0, -1.0})
      for (double s = step; s <= std::min(t, 1.0); s += step) {
        const Eigen::VectorXd x = q + sign * s * dir;
        if (!kin.within_limits(x)) break;
        EXPECT_TRUE(exact.is_free(x)) << "certified " << t << " from q = " << q.transpose() << " along "
                                      << (sign * dir).transpose() << " but FCL finds a collision at " << s << ": "
                                      << exact.check(x).contact;
        if (!exact.is_free(x)) return walked;
      }
  }
  return walked;
}

}  // namespace dmgplace::test
