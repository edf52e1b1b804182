// The two layers at the home pose; self-collision: allowed pairs, and the pairs the scalar
// passes flag.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "collision_fixtures.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"
#include "lane_rounds.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;
using test::random_q;

TEST(Collision, HomePoseIsFreeAndObstaclesAtTheHandAreCaught) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  Eigen::VectorXd home(7);
  home << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  Scene empty;
  empty.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 3, 3})}});
  ExactChecker exact(kin, empty);
  EXPECT_TRUE(exact.check(home).free()) << exact.check(home).contact;
  auto sdf = test::analytic_sdf(
      empty, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  SphereFieldChecker fast(kin, arm.spheres, sdf, 0.3);
  // Home folds link 7 close to link 5: the spheres may not tell, the two layers must.
  EXPECT_TRUE(TwoLayerChecker(fast, exact).is_free(home));
  // A box around the tool center point collides in both layers.
  Scene blocked = empty;
  const Eigen::Vector3d tcp = kin.tip_pose(home).translation();
  blocked.objects.push_back({"block", {box({0.05, 0.05, 0.05}, tcp)}});
  ExactChecker exact2(kin, blocked);
  auto sdf2 = test::analytic_sdf(
      blocked, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  SphereFieldChecker fast2(kin, arm.spheres, sdf2, 0.3);
  EXPECT_FALSE(exact2.is_free(home));
  EXPECT_FALSE(fast2.is_free(home));
  EXPECT_NE(exact2.check(home).contact.find("block"), std::string::npos);
}

TEST(Collision, SelfCollisionRespectsAllowedPairs) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  Scene empty;
  empty.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 3, 3})}});
  ExactChecker exact(kin, empty);
  auto sdf = test::analytic_sdf(
      empty, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)), 0.02, 0.3);
  SphereFieldChecker fast(kin, arm.spheres, sdf, 0.3);
  std::mt19937_64 rng(9);
  int self_hits = 0;
  for (int i = 0; i < 5000; ++i) {
    Eigen::VectorXd q = random_q(kin, rng);
    auto e = exact.check(q);
    self_hits += !e.self_free;
    if (fast.is_free(q)) {
      ASSERT_TRUE(e.free()) << e.contact;
    }
  }
  EXPECT_GT(self_hits, 0) << "random configurations of a 7-DOF arm fold into themselves sometimes";
}

// The scalar passes' pair test (SphereFieldChecker::pair_contact: each body's spheres in its own
// frame, four at a time) flags exactly the link pairs whose spheres a world-frame loop over every
// sphere pair finds overlapping (padding counted once), on each SIMD path; the certified check's
// own loop flags the same ones.
TEST(Collision, FlaggedSelfPairsAreThoseWhoseSpheresOverlap) {
  Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  kin.set_joint_value("dmgarm_finger_joint1", 0.02);
  Scene empty;
  empty.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 3, 3})}});
  auto sdf = test::analytic_sdf(
      empty, Eigen::AlignedBox3d(Eigen::Vector3d(-1.6, -1.6, -1.0), Eigen::Vector3d(1.6, 1.6, 2.0)), 0.04, 0.3);
  const double padding = 0.005;
  const SphereFieldChecker fast(kin, arm.spheres, sdf, 0.3, padding);
  const auto moving = kin.moving_links();
  auto allowed = [&](int a, int b) {
    for (auto [x, y] : kin.model().allowed_pairs)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
  };
  std::vector<Eigen::Isometry3d> poses;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    std::mt19937_64 rng(21);
    int proven = 0, overflow = 0;
    std::set<std::set<std::pair<int, int>>> kinds;  // sets of flagged pairs seen
    for (int n = 0; n < 3000; ++n) {
      const Eigen::VectorXd q = random_q(kin, rng);
      kin.link_poses(q, poses);
      std::set<std::pair<int, int>> expect;
      for (const auto& s : arm.spheres)
        for (const auto& t : arm.spheres) {
          if (s.link >= t.link || (!moving[std::size_t(s.link)] && !moving[std::size_t(t.link)]) ||
              allowed(s.link, t.link))
            continue;
          const double r = s.radius + t.radius + padding;
          if ((poses[std::size_t(s.link)] * s.center - poses[std::size_t(t.link)] * t.center).squaredNorm() < r * r)
            expect.insert({s.link, t.link});
        }
      const Eigen::VectorXd dir = (random_q(kin, rng) - q).normalized();
      for (const SphereCheck& got : {fast.check(q), fast.check_along(q, dir, 0.05)}) {
        if (got.pairs_overflow) {  // more pairs than a check lists
          EXPECT_GT(expect.size(), std::size_t(SphereCheck::kMaxPairs));
          ++overflow;
          continue;
        }
        if (got.proven_collision) {  // the self pass stopped at a pair whose inner balls overlap
          EXPECT_FALSE(expect.empty());
          ++proven;
          continue;
        }
        std::set<std::pair<int, int>> pairs;
        for (int k = 0; k < got.pair_count; ++k)
          pairs.insert(std::minmax(got.pairs[std::size_t(k)].first, got.pairs[std::size_t(k)].second));
        ASSERT_EQ(pairs, expect) << "configuration " << n << " on the " << to_string(path) << " path";
        EXPECT_EQ(got.self_free, expect.empty());
        kinds.insert(expect);
      }
    }
    // (This arm's wrist spheres overlap in every configuration: its self tables settle them.)
    EXPECT_GT(kinds.size(), 50u) << "random configurations fold the arm into itself in many ways";
    EXPECT_GT(proven, 0);
    EXPECT_LT(overflow, 300);
  }
}
