// ExactChecker (FCL): moved to another scene, and links at given poses.
#include <gtest/gtest.h>

#include <random>
#include <utility>

#include "collision_fixtures.hpp"
#include "lane_rounds.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;
using test::random_q;

// A checker moved to another scene keeps the robot's geometry and answers as one built there.
TEST(ExactChecker, WithSceneAnswersAsACheckerBuiltForThatScene) {
  ShelfWorld w;
  const ExactChecker empty(w.kin, Scene{});
  const ExactChecker moved = empty.with_scene(w.scene), fresh(w.kin, w.scene);
  std::mt19937_64 rng(29);
  int collide = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::VectorXd q = random_q(w.kin, rng);
    const ExactCheck a = moved.check(q), b = fresh.check(q);
    ASSERT_EQ(a.environment_free, b.environment_free);
    ASSERT_EQ(a.self_free, b.self_free);
    ASSERT_TRUE(empty.check(q).environment_free);
    collide += !a.environment_free;
  }
  EXPECT_GT(collide, 10);
}

// links_free (links at given poses, the placement's hand check) must answer as the exact layer
// does for the same links placed by forward kinematics, one link at a time and all together.
TEST(ExactChecker, LinksFreeAtGivenPosesAgreesWithFcl) {
  ShelfWorld w;
  const ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(29);
  std::vector<Eigen::Isometry3d> poses;
  const int links = int(w.arm.model.links.size());
  int free = 0, colliding = 0;
  for (int n = 0; n < 400; ++n) {
    w.kin.link_poses(random_q(w.kin, rng), poses);
    std::vector<std::pair<int, Eigen::Isometry3d>> all;
    bool all_free = true;
    for (int a = 0; a < links; ++a) {
      if (w.arm.model.links[std::size_t(a)].collision.empty()) continue;
      const bool fcl = exact.links_environment_free(poses, &a, 1, false, nullptr);
      ASSERT_EQ(exact.links_free({{a, poses[std::size_t(a)]}}), fcl)
          << w.arm.model.links[std::size_t(a)].name << ", sample " << n;
      ++(fcl ? free : colliding);
      all_free = all_free && fcl;
      all.emplace_back(a, poses[std::size_t(a)]);
    }
    EXPECT_EQ(exact.links_free(all), all_free) << "sample " << n;
  }
  EXPECT_GT(free, 1000);
  EXPECT_GT(colliding, 100);
}
