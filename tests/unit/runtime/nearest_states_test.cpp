#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "dmgplace/runtime/motion/nearest_states.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

using dmgplace::runtime::NearestStates;
using dmgplace::runtime::SimdPath;

namespace {
double squared(const double* a, const double* b, std::size_t dim) {
  double s = 0;
  for (std::size_t k = 0; k < dim; ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return s;
}
}  // namespace

// The nearest point is the brute-force nearest on both sides of the switch from the scan to GNAT
// (and right at it), for uniform points and for points in tight clusters (an RRT's tree along a
// corridor), on the portable and the AVX2 scan: equal distances, so a tie may name either point.
TEST(NearestStates, IsTheBruteForceNearestOnBothSidesOfTheSwitchToGnat) {
  const dmgplace::runtime::ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2})
    for (const bool clustered : {false, true}) {
      dmgplace::runtime::force_simd_path(path);  // Avx2 stays portable on a CPU without it
      const std::size_t dim = 7;
      NearestStates set(dim);
      std::mt19937_64 rng(clustered ? 5 : 4);
      std::uniform_real_distribution<double> u(-3, 3);
      std::normal_distribution<double> g(0, 0.02);
      std::vector<double> center(dim), q(dim);
      int checked = 0;
      for (std::size_t n = 1; n <= NearestStates::kScan + 600; ++n) {
        if (!clustered || n % 200 == 1)
          for (auto& c : center) c = u(rng);
        for (std::size_t k = 0; k < dim; ++k) q[k] = clustered ? center[k] + g(rng) : u(rng);
        ASSERT_EQ(set.add(q.data()), n - 1);
        ASSERT_EQ(set.size(), n);
        const bool near_switch = n + 3 >= NearestStates::kScan && n <= NearestStates::kScan + 3;
        if (n % 997 != 0 && n > 40 && !near_switch && n != NearestStates::kScan + 600) continue;
        for (int t = 0; t < 20; ++t) {
          for (std::size_t k = 0; k < dim; ++k) q[k] = clustered && t % 2 ? center[k] + 5 * g(rng) : u(rng);
          double best = std::numeric_limits<double>::infinity();
          for (std::size_t i = 0; i < set.size(); ++i) best = std::min(best, squared(set.point(i), q.data(), dim));
          const std::size_t got = set.nearest(q.data());
          ASSERT_LT(got, set.size());
          ASSERT_EQ(squared(set.point(got), q.data(), dim), best)
              << n << " points, clustered " << clustered << ", " << to_string(path);
          ++checked;
        }
        // A stored point is its own nearest.
        const std::size_t i = std::size_t(rng() % set.size());
        ASSERT_EQ(squared(set.point(set.nearest(set.point(i))), set.point(i), dim), 0.0);
      }
      EXPECT_GT(checked, 500);
    }
}

TEST(NearestStates, RefusesAnEmptySetAndNoDimensions) {
  EXPECT_THROW(NearestStates(0), std::invalid_argument);
  NearestStates set(3);
  const double q[3] = {0, 0, 0};
  EXPECT_THROW(set.nearest(q), std::logic_error);
}

// Removed points are never the answer, before and after the switch to GNAT (which keeps them and
// defers to the scan when it names one); the rest stays the brute-force nearest. Removing every
// point leaves nothing to ask.
TEST(NearestStates, RemovedPointsAreNeverTheNearestOnEitherSideOfTheSwitch) {
  const std::size_t dim = 3;
  NearestStates set(dim);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<char> removed;
  std::vector<double> q(dim);
  int checked = 0;
  for (std::size_t n = 1; n <= NearestStates::kScan + 400; ++n) {
    for (auto& x : q) x = u(rng);
    set.add(q.data());
    removed.push_back(0);
    if (rng() % 3 == 0) {  // a third of the points go, some just added, some long stored
      const std::size_t i = rng() % 2 ? n - 1 : std::size_t(rng() % n);
      set.remove(i);
      removed[i] = 1;
    }
    if (n % 1999 != 0 && n != NearestStates::kScan + 400) continue;
    for (int t = 0; t < 20; ++t) {
      // Half the queries sit on a removed point: its removal is what decides them.
      std::size_t on = std::size_t(rng() % n);
      if (t % 2 == 0)
        for (std::size_t k = 0; k < n && !removed[on]; ++k) on = (on + 1) % n;
      for (std::size_t k = 0; k < dim; ++k) q[k] = t % 2 == 0 ? set.point(on)[k] : u(rng);
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < n; ++i)
        if (!removed[i]) best = std::min(best, squared(set.point(i), q.data(), dim));
      const std::size_t got = set.nearest(q.data());
      ASSERT_FALSE(removed[got]) << n << " points";
      ASSERT_EQ(squared(set.point(got), q.data(), dim), best) << n << " points";
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
  NearestStates two(dim);
  two.add(q.data());
  two.add(q.data());
  two.remove(0);
  EXPECT_EQ(two.nearest(q.data()), 1u);
  two.remove(1);
  EXPECT_THROW(two.nearest(q.data()), std::logic_error);
  EXPECT_THROW(two.remove(2), std::out_of_range);
}
