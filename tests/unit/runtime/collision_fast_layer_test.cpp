// The fast layer (SphereFieldChecker) in each of its forms, and the two-layer checker over it.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "collision_fixtures.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "gap_certificates.hpp"
#include "lane_rounds.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;
using test::random_q;

INSTANTIATE_TEST_SUITE_P(Collision, FastLayer,
                         ::testing::Values(Form::FieldOnly, Form::WithExactPrimitives, Form::ExactPrimitivesNoField,
                                           Form::FieldWithManyPrimitives),
                         [](const auto& info) {
                           return info.param == Form::FieldOnly                ? "FieldOnly"
                                  : info.param == Form::WithExactPrimitives    ? "WithExactPrimitives"
                                  : info.param == Form::ExactPrimitivesNoField ? "ExactPrimitivesNoField"
                                                                               : "FieldWithManyPrimitives";
                         });

// A scene of a few primitives needs no field: the checker built without one answers exactly as
// the one with a field beside the same primitives (which it never reads), state by state, along
// directions and in lanes; a scene the primitives cannot carry alone is refused.
TEST(FastLayerWithoutField, AnswersAsWithAFieldItNeverReads) {
  ShelfWorld w;
  const auto tables = test::self_distance_tables(w.kin, w.arm.spheres);
  const auto prims = PrimitiveObstacles::from_scene(w.scene);
  SphereFieldChecker with_field(w.kin, w.arm.spheres, w.sdf, 0.3);
  with_field.set_self_tables(tables);
  with_field.set_exact_obstacles(prims);
  SphereFieldChecker without(w.kin, w.arm.spheres, prims);
  without.set_self_tables(tables);
  EXPECT_TRUE(with_field.has_field());
  EXPECT_FALSE(without.has_field());
  std::mt19937_64 rng(23);
  int free = 0;
  for (int round = 0; round < 400; ++round) {
    std::vector<Eigen::VectorXd> qs;
    const double* ptr[LinkPoseLanesD::kLanes];
    for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) qs.push_back(random_q(w.kin, rng));
    for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
    const Eigen::VectorXd dir = random_q(w.kin, rng) - qs[0];
    ASSERT_EQ(with_field.free_lanes(ptr), without.free_lanes(ptr));
    ASSERT_EQ(with_field.free_lanes_along(ptr, LinkPoseLanesD::kLanes, dir, 0.05),
              without.free_lanes_along(ptr, LinkPoseLanesD::kLanes, dir, 0.05));
    const SphereCheck a = with_field.check_along(qs[0], dir), b = without.check_along(qs[0], dir);
    ASSERT_EQ(a.free(), b.free());
    ASSERT_EQ(a.env_link_count, b.env_link_count);
    ASSERT_EQ(a.pair_count, b.pair_count);
    ASSERT_EQ(a.proven_collision, b.proven_collision);
    ASSERT_EQ(a.free_distance, b.free_distance);
    free += a.free();
  }
  EXPECT_GT(free, 40);
  Scene many = w.scene;
  for (int k = 0; k < 64; ++k) many.objects.push_back({"speck", {box({0.01, 0.01, 0.01}, {0.1 * k, 4.0, 3.0})}});
  EXPECT_THROW(SphereFieldChecker(w.kin, w.arm.spheres, PrimitiveObstacles::from_scene(many)), Error);
  EXPECT_THROW(SphereFieldChecker(w.kin, w.arm.spheres, std::shared_ptr<const PrimitiveObstacles>()), Error);
  EXPECT_THROW(without.set_exact_obstacles(nullptr), Error);
}

TEST_P(FastLayer, NeverSaysFreeWhereExactLayerCollides) {
  ShelfWorld w;
  const auto& [arm, kin, scene, sdf] = w;
  SphereFieldChecker fast = make(w);
  ExactChecker exact(kin, scene);
  TwoLayerChecker both_layers(fast, exact);
  std::mt19937_64 rng(42);
  int fast_free = 0, exact_free = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd q = random_q(kin, rng);
    const bool f = fast.is_free(q), e = exact.is_free(q);
    fast_free += f;
    exact_free += e;
    ASSERT_FALSE(f && !e) << "fast layer said free where FCL collides: q = " << q.transpose() << " ("
                          << exact.check(q).contact << ")";
    ASSERT_EQ(both_layers.is_free(q), e) << "the two-layer answer must be the exact answer";
  }
  // The sphere layer must settle the environment on its own most of the time, or it is no layer.
  const long full = both_layers.counters().exact_full.load();
  EXPECT_LT(full, long(n) / 2) << "full exact checks: " << full << " of " << n;
  // The inner balls prove collisions, from the exact primitives or from the field alone (an
  // obstacle's surface within a ball's radius of its center, by the field's upper bound): each
  // one agreed with FCL above.
  EXPECT_GT(both_layers.counters().proven_collisions.load(), long(n) / 50);
  RecordProperty("fast_free", fast_free);
  RecordProperty("exact_full", int(full));
  RecordProperty("exact_free", exact_free);
}

// The certified free distance is a proof: every configuration within it along the direction is
// free for FCL (random directions and random points of the certified stretch), self-distance
// tables included.
TEST_P(FastLayer, CertifiedFreeDistanceIsFreeForFclAlongTheWholeStretch) {
  ShelfWorld w;
  const auto& [arm, kin, scene, sdf] = w;
  SphereFieldChecker fast = make(w);
  fast.set_self_tables(test::self_distance_tables(kin, arm.spheres));
  ExactChecker exact(kin, scene);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1);
  int certified = 0;
  double longest = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::VectorXd q = random_q(kin, rng);
    Eigen::VectorXd dir(kin.dof());
    for (int j = 0; j < kin.dof(); ++j) dir[j] = g(rng);
    dir.normalize();
    const SphereCheck c = fast.check_along(q, dir);
    EXPECT_EQ(c.free(), fast.check(q).free());
    if (!c.free()) continue;
    ASSERT_GE(c.free_distance, 0.0);
    // A caller that needs less gets a cheaper certificate: at least what it asked for (or all
    // there is), and just as sound.
    const double enough = std::uniform_real_distribution<double>(0.0, 0.05)(rng);
    const double limited = fast.check_along(q, dir, enough).free_distance;
    EXPECT_GE(limited, std::min(enough, c.free_distance) - 1e-12);
    EXPECT_LE(limited, c.free_distance + 1e-12) << "less work cannot prove more";
    if (c.free_distance <= 0) continue;
    ++certified;
    longest = std::max(longest, std::min(c.free_distance, 10.0));
    // Walk both ways in 2 mrad steps to the first FCL contact (or the joint limits): the
    // certificates must stop short of it.
    for (const double certificate : {c.free_distance, limited})
      for (const double sign : {1.0, -1.0}) {
        for (double t = 0.002; t <= std::min(certificate, 3.0); t += 0.002) {
          const Eigen::VectorXd x = q + sign * t * dir;
          if (!kin.within_limits(x)) break;  // beyond the limits nothing is claimed
          ASSERT_TRUE(exact.is_free(x)) << "certified " << certificate << " from q = " << q.transpose() << " but "
                                        << exact.check(x).contact << " at t = " << sign * t;
        }
      }
  }
  EXPECT_GT(certified, 100) << "the certificate must be non-trivial in free space";
  EXPECT_GT(longest, 0.02);
  RecordProperty("certified", certified);
}

// Every check and span lane check of one motion shares its direction's static speeds (kept per thread,
// SphereFieldChecker::static_speeds). A checker and its per-grasp copy (more bodies and pairs),
// asked in turn along one direction, must each answer as when asked alone.
TEST_P(FastLayer, CheckersAskedInTurnAlongOneDirectionAnswerAsAlone) {
  ShelfWorld w;
  const auto& [arm, kin, scene, sdf] = w;
  SphereFieldChecker fast = make(w);
  fast.set_self_tables(test::self_distance_tables(kin, arm.spheres));
  AttachedSpheres object;  // a 12 cm rod held along the tool axis
  object.link = arm.model.link_index("dmgarm_tcp");
  for (int k = 0; k < 4; ++k) {
    object.centers.emplace_back(0, 0, 0.03 + 0.03 * k);
    object.radii.push_back(0.03);
  }
  object.touching_links = {arm.model.link_index("dmgarm_leftfinger"), arm.model.link_index("dmgarm_rightfinger")};
  const SphereFieldChecker held = fast.with_attached(object);
  std::mt19937_64 rng(21);
  std::normal_distribution<double> g(0, 1);
  auto unit = [&] {
    Eigen::VectorXd d(kin.dof());
    for (int j = 0; j < kin.dof(); ++j) d[j] = g(rng);
    return Eigen::VectorXd(d.normalized());
  };
  int differ = 0, proven = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::VectorXd q = random_q(kin, rng), dir = unit(), other = unit();
    const Eigen::VectorXd far = q + 0.02 * dir;
    const double* lanes[2] = {q.data(), far.data()};
    // Alone: another direction asked just before. A certificate asked to last `enough` reads the
    // static speeds for what it may skip; a span lane check widens by them.
    const double enough = 0.03;
    (void)fast.check_along(q, other, enough);
    const double held_alone = held.check_along(q, dir, enough).free_distance;
    (void)fast.check_along(q, other, enough);
    const double base_alone = fast.check_along(q, dir, enough).free_distance;
    (void)fast.check_along(q, other, enough);
    const std::uint32_t held_lanes_alone = held.free_lanes_along(lanes, 2, dir, 0.01);
    // In turn, the same direction throughout.
    const double base = fast.check_along(q, dir, enough).free_distance;
    const double with_object = held.check_along(q, dir, enough).free_distance;
    const std::uint32_t held_lanes = held.free_lanes_along(lanes, 2, dir, 0.01);
    const double base_again = fast.check_along(q, dir, enough).free_distance;
    EXPECT_EQ(base, base_alone);
    EXPECT_EQ(base_again, base_alone);
    EXPECT_EQ(with_object, held_alone);
    EXPECT_EQ(held_lanes, held_lanes_alone);
    differ += base_alone != held_alone;
    proven += held_alone > 0;
  }
  EXPECT_GT(differ, 3) << "the held object must change some certificates";
  EXPECT_GT(proven, 50);
}

// The two layers share one set of link poses per query, so they must pose the same robot.
TEST(TwoLayer, RefusesLayersOnDifferentKinematics) {
  ShelfWorld w;
  Kinematics other(w.arm.model, "dmgarm_link0", "dmgarm_tcp");
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  EXPECT_THROW(TwoLayerChecker(fast, ExactChecker(other, w.scene)), Error);
  EXPECT_NO_THROW(TwoLayerChecker(fast, ExactChecker(w.kin, w.scene)));
}

// Where the spheres flag links (near the scene, pairs close), exact clearances certify the state
// (TwoLayerChecker::free_distance): never a collision, and every certified stretch free for FCL.
TEST(TwoLayer, ExactGapCertificatesKeepEveryStateFree) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  const ExactChecker exact(w.kin, w.scene);
  ASSERT_TRUE(exact.gaps_are_cheap()) << "the built-in arm and the shelf are primitives: gaps on by default";
  const TwoLayerChecker both(fast, exact);
  double longest = 0;
  const int walked = test::walk_gap_certificates(both, exact, 3000, 17, &longest);
  EXPECT_GT(walked, 50) << "flagged states must get exact certificates";
  EXPECT_GT(longest, 0.01);
  RecordProperty("walked", walked);
}

// Plain checks ask gaps for a sign only (enough = 0): it must be the full gap's sign, on random
// states of the shelf and where a bounding ball alone would pass: an obstacle just off a box's
// corner touches the box's ball there, closer than the 0.1 mm a computed gap gives up.
TEST(TwoLayer, AGapsSignQueryAgreesWithTheFullGap) {
  ShelfWorld w;
  const ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(23);
  std::vector<Eigen::Isometry3d> poses;
  const int links = int(w.arm.model.links.size());
  int positive = 0, other = 0;
  auto agree = [&](double sign, double full, const std::string& what) {
    ASSERT_EQ(sign > 0, full > 0) << what << ": sign query " << sign << ", full gap " << full;
    ++(full > 0 ? positive : other);
  };
  for (int n = 0; n < 300; ++n) {
    w.kin.link_poses(random_q(w.kin, rng), poses);
    for (int a = 0; a < links; ++a) {
      if (w.arm.model.links[std::size_t(a)].collision.empty()) continue;
      agree(exact.link_environment_gap(poses, a, 0.0), exact.link_environment_gap(poses, a),
            w.arm.model.links[std::size_t(a)].name);
      for (int b = a + 1; b < links; ++b)
        if (!w.arm.model.links[std::size_t(b)].collision.empty())
          agree(exact.link_pair_gap(poses, a, b, 0.0), exact.link_pair_gap(poses, a, b), "pair");
    }
  }
  EXPECT_GT(positive, 1000);
  EXPECT_GT(other, 100);

  const int base = w.arm.model.link_index("dmgarm_link0");
  const auto& shapes = w.arm.model.links[std::size_t(base)].collision;
  ASSERT_EQ(shapes.size(), 1u);
  ASSERT_EQ(shapes[0].type, ShapeType::Box);
  w.kin.link_poses(Eigen::VectorXd::Zero(w.kin.dof()), poses);
  const Eigen::Isometry3d pose = poses[std::size_t(base)] * shapes[0].origin;
  const Eigen::Vector3d corner = pose * Eigen::Vector3d(shapes[0].size / 2);
  const Eigen::Vector3d out = (corner - pose.translation()).normalized();
  for (const double d : {2e-5, 5e-5, 9e-5, 3e-4, 1e-2}) {
    Shape ball;
    ball.type = ShapeType::Sphere;
    ball.size = Eigen::Vector3d(0.005, 0, 0);
    ball.origin.translation() = corner + (0.005 + d) * out;
    Scene scene;
    scene.objects.push_back({"ball", {ball}});
    const ExactChecker near(w.kin, scene);
    const double full = near.link_environment_gap(poses, base), sign = near.link_environment_gap(poses, base, 0.0);
    EXPECT_EQ(full > 0, d > 1e-4) << "a gap counts only beyond 0.1 mm; " << d << " m off the corner: " << full;
    EXPECT_EQ(sign > 0, full > 0) << d << " m off the corner: sign query " << sign << ", full gap " << full;
  }
}
