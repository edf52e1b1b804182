// The one segment checker: the states it visits are at most `resolution` apart in Euclidean joint
// space (the planners' metric), end at b, never revisit a, and path_valid / ExactChecker agree.
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/runtime/motion/segment_check.hpp"

using namespace dmgplace::runtime;

TEST(SegmentCheck, StatesAreAtMostOneResolutionApartInL2AndEndAtB) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 9;
    Eigen::VectorXd a(n), b(n);
    for (int i = 0; i < n; ++i) a[i] = u(rng), b[i] = a[i] + 0.3 * u(rng);
    const double res = 0.01 + 0.05 * (u(rng) + 1);
    std::vector<Eigen::VectorXd> seen;
    EXPECT_TRUE(segment_valid(a, b, res, [&](const Eigen::VectorXd& q) {
      seen.push_back(q);
      return true;
    }));
    ASSERT_FALSE(seen.empty());
    EXPECT_EQ(int(seen.size()), segment_steps(a, b, res));
    EXPECT_TRUE(seen.back().isApprox(b, 1e-15) || (seen.back() - b).norm() == 0);
    Eigen::VectorXd prev = a;
    for (const auto& q : seen) {
      EXPECT_LE((q - prev).norm(), res * (1 + 1e-9));
      EXPECT_GT((q - a).norm(), 0) << "a is the caller's, not checked again";
      prev = q;
    }
  }
}

TEST(SegmentCheck, DiagonalMotionsAreSteppedByTheirLengthNotTheLargestJointChange) {
  // 7 joints each moving 0.1 rad: 0.265 rad of joint-space length, 6 states at 0.05 (a
  // largest-joint-change metric would check only 2 and miss what lies between).
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(7), b = Eigen::VectorXd::Constant(7, 0.1);
  int calls = 0;
  segment_valid(a, b, 0.05, [&](const Eigen::VectorXd&) { return ++calls, true; });
  EXPECT_EQ(calls, 6);
}

TEST(SegmentCheck, AnInvalidStateAnywhereFailsTheSegmentAndThePath) {
  // Invalid inside a thin slab around x = 0.5: a coarse step jumps over it, the right one does not.
  const auto valid = [](const Eigen::VectorXd& q) { return std::abs(q[0] - 0.5) > 0.004; };
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(2), b = Eigen::Vector2d(1.0, 0.0);
  EXPECT_FALSE(segment_valid(a, b, 0.005, valid));
  EXPECT_TRUE(segment_valid(a, b, 0.35, valid)) << "3 steps: 0.333, 0.667, 1 skip the slab";
  EXPECT_FALSE(path_valid({{0, 0}, {0.2, 0}, {1, 0}}, valid, 0.005));
  EXPECT_TRUE(path_valid({{0, 0}, {0.2, 0}, {0.4, 0}}, valid, 0.005));
  EXPECT_FALSE(path_valid({{0.5, 0}}, valid, 0.005)) << "a single invalid state";
  EXPECT_FALSE(path_valid({}, valid, 0.005)) << "no path is not a valid path";
}

TEST(SegmentCheck, NonFiniteEndsAreCheckedNotSkipped) {
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd b(2);
  b << std::nan(""), 0;
  int calls = 0;
  EXPECT_FALSE(segment_valid(a, b, 0.05, [&](const Eigen::VectorXd& q) { return ++calls, q.allFinite(); }));
  EXPECT_EQ(calls, 1);
}
