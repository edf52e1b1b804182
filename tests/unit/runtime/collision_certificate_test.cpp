// Certified free distances (check_along) and the exact layer's link and pair times.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <string>

#include "collision_fixtures.hpp"
#include "lane_rounds.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;
using test::random_q;

// Sharper than FCL for the scene: with exact primitives the fast layer's environment answer is
// exact for its spheres, so along a certificate every sphere must stay clear of the scene (what
// the speed bounds, static, Gronwall and Taylor, promise, with no slack from the spheres' excess
// over the meshes), directional ones included (spheres sliding along the board and the wall: a
// share of the certificates must be a quarter past their isotropic estimate or more). Self-collision, partly
// settled by tables, is checked by FCL.
TEST(Certificate, KeepsEverySphereClearOfTheSceneAlongTheStretch) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  int certified = 0, directional = 0;
  double longest = 0;
  auto clear = [&](const Eigen::VectorXd& x) { return fast.check(x).environment_free && exact.is_free(x); };
  for (int i = 0; i < 3000; ++i) {
    const Eigen::VectorXd q = random_q(w.kin, rng);
    Eigen::VectorXd dir(w.kin.dof());
    for (int j = 0; j < w.kin.dof(); ++j) dir[j] = g(rng);
    dir.normalize();
    const SphereCheck c = fast.check_along(q, dir);
    // Near the scene, where certificates are short and every bound counts.
    if (!c.free() || c.free_distance <= 0 || c.min_clearance > 0.03) continue;
    ++certified;
    EXPECT_LE(c.isotropic_distance, c.free_distance);
    if (c.free_distance > 1.25 * c.isotropic_distance) ++directional;
    const double step = std::min(0.001, c.free_distance / 20);
    for (const double sign : {1.0, -1.0}) {
      double t = step;
      for (; t <= std::min(c.free_distance, 1.0); t += step) {
        const Eigen::VectorXd x = q + sign * t * dir;
        if (!w.kin.within_limits(x)) break;
        ASSERT_TRUE(clear(x)) << "certified " << c.free_distance << " from q = " << q.transpose() << " along "
                              << (sign * dir).transpose() << " but a sphere touches the scene at t = " << t;
      }
    }
    longest = std::max(longest, c.free_distance);
  }
  EXPECT_GT(certified, 100);
  EXPECT_GT(longest, 0.02);
  EXPECT_GT(directional, 20) << "of " << certified;
  RecordProperty("certified", certified);
  RecordProperty("directional", directional);
}

// The same for the whole robot, self pairs included (FCL judges), and for the callers that need
// only so much (`enough`): a pair's gap limits the certificate, and sphere pairs farther apart
// than the gap or than `need` are skipped, so those skips must keep it valid.
TEST(Certificate, KeepsTheRobotClearOfItselfAndTheSceneForEveryEnough) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  ExactChecker exact(w.kin, w.scene);
  std::mt19937_64 rng(17);
  int certified = 0;
  for (int i = 0; i < 400; ++i) {
    // Where it matters: a little joint motion (0.15 rad) short of a collision, heading for it.
    const Eigen::VectorXd a = random_q(w.kin, rng), b = random_q(w.kin, rng);
    if (!exact.is_free(a) || exact.is_free(b)) continue;
    double lo = 0, hi = 1;
    for (int k = 0; k < 30; ++k) (exact.is_free(a + (lo + hi) / 2 * (b - a)) ? lo : hi) = (lo + hi) / 2;
    const Eigen::VectorXd dir = (b - a).normalized();
    const Eigen::VectorXd q = a + lo * (b - a) - 0.15 * dir;
    if (!w.kin.within_limits(q)) continue;
    for (const double enough : {std::numeric_limits<double>::infinity(), 0.2, 0.05}) {
      const SphereCheck c = fast.check_along(q, dir, enough);
      if (!c.free() || c.free_distance <= 0) continue;
      ++certified;
      const double reach = std::min(c.free_distance, 1.0), step = std::min(reach / 40, 0.002);
      for (const double sign : {1.0, -1.0})
        for (double t = step; t <= reach; t += step) {
          const Eigen::VectorXd x = q + sign * t * dir;
          if (!w.kin.within_limits(x)) break;
          ASSERT_TRUE(exact.is_free(x)) << "certified " << c.free_distance << " (enough " << enough
                                        << ") from q = " << q.transpose() << " along " << (sign * dir).transpose()
                                        << " but t = " << t << " collides";
        }
    }
  }
  EXPECT_GT(certified, 100);
}

// The field stops at its band: far from every obstacle a body's certificate comes from its
// bounding sphere against the exact primitives, not from the band's "at least 0.3 m". Turning the
// base with a box 3 m away, the certificate is never shorter than the field's alone, 1.5x longer
// in the median (then the base link's pairs limit it; 1.0x before), and free for FCL.
TEST(Certificate, FarFromTheSceneTheFieldsBandDoesNotCapIt) {
  const Arm arm = built_in_arm();
  Kinematics kin(arm.model, "dmgarm_link0", "dmgarm_tcp");
  kin.set_joint_value("dmgarm_finger_joint1", 0.03);
  Scene scene;
  scene.objects.push_back({"far", {box({0.1, 0.1, 0.1}, {3, 0, 0.5})}});
  const double band = 0.3;
  SphereFieldChecker field_only(
      kin, arm.spheres,
      test::analytic_sdf(scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.4), Eigen::Vector3d(1.2, 1.2, 1.6)),
                         0.02, band),
      band);
  field_only.set_self_tables(test::self_distance_tables(kin, arm.spheres));
  SphereFieldChecker fast = field_only;
  fast.set_exact_obstacles(PrimitiveObstacles::from_scene(scene));
  ExactChecker exact(kin, scene);
  Eigen::VectorXd base_turn = Eigen::VectorXd::Zero(kin.dof());
  base_turn[0] = 1;
  std::mt19937_64 rng(5);
  std::vector<double> with_exact, with_field;
  for (int i = 0; i < 300; ++i) {
    const Eigen::VectorXd q = random_q(kin, rng);
    const SphereCheck c = fast.check_along(q, base_turn);
    if (!c.free()) continue;
    const double field = field_only.check_along(q, base_turn).free_distance;
    EXPECT_GE(c.free_distance, field - 1e-12) << "q = " << q.transpose();
    with_exact.push_back(c.free_distance);
    with_field.push_back(field);
    if (with_exact.size() > 40) continue;
    for (const double sign : {1.0, -1.0})
      for (double t = 0.005; t <= std::min(c.free_distance, 1.5); t += 0.005) {
        const Eigen::VectorXd x = q + sign * t * base_turn;
        if (!kin.within_limits(x)) break;
        ASSERT_TRUE(exact.is_free(x)) << "certified " << c.free_distance << " from q = " << q.transpose() << " but "
                                      << exact.check(x).contact << " at t = " << sign * t;
      }
  }
  ASSERT_GT(with_exact.size(), 100u);
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  EXPECT_GT(median(with_exact), 1.5 * median(with_field));
}

// link_time and pair_time (the exact layer's certificates, from the speed bounds check_along uses)
// hold for every point of a link's spheres: within the time given for a gap, no point moves that
// far, and no point of one link changes its distance to a point of the other by that much. Gaps
// of 2-20 mm keep the times short, where the bounds are tight: a lever arm taken too short, or a
// joint left out, shows here (halving the arms fails it).
TEST(Certificate, LinkAndPairTimesKeepEveryPointWithinTheGap) {
  ShelfWorld w;
  const SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  std::mt19937_64 rng(23);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  // Per link: its spheres' centers and points on their surfaces (link frame).
  std::vector<std::vector<Eigen::Vector3d>> points(w.kin.model().links.size());
  for (const auto& sp : w.arm.spheres) {
    points[std::size_t(sp.link)].push_back(sp.center);
    for (int k = 0; k < 6; ++k)
      points[std::size_t(sp.link)].push_back(sp.center +
                                             sp.radius * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  }
  const auto moving = w.kin.moving_links();
  std::vector<int> links;
  for (std::size_t l = 0; l < points.size(); ++l)
    if (moving[l] && !points[l].empty()) links.push_back(int(l));
  ASSERT_GE(links.size(), 5u);
  auto world = [&](const Eigen::VectorXd& x, int link) {
    std::vector<Eigen::Isometry3d> poses;
    w.kin.link_poses(x, poses);
    std::vector<Eigen::Vector3d> out;
    for (const auto& p : points[std::size_t(link)]) out.push_back(poses[std::size_t(link)] * p);
    return out;
  };
  int link_cases = 0, pair_cases = 0;
  double tightest = 0;  // the largest share of the gap any point used
  for (int trial = 0; trial < 600; ++trial) {
    const Eigen::VectorXd q = random_q(w.kin, rng);
    Eigen::VectorXd dir(w.kin.dof());
    for (int j = 0; j < w.kin.dof(); ++j) dir[j] = g(rng);
    dir.normalize();
    std::vector<Eigen::Isometry3d> poses;
    w.kin.link_poses(q, poses);
    const double gap = 0.002 + 0.018 * u(rng);
    const int a = links[std::size_t(rng() % links.size())], b = links[std::size_t(rng() % links.size())];
    const double tl = fast.link_time(poses, a, gap, dir);
    ASSERT_GT(tl, 0.0);
    const auto pa = world(q, a);
    for (double t = tl / 8; t <= std::min(tl, 2.0); t += tl / 8) {
      const auto xa = world(q + t * dir, a);
      for (std::size_t k = 0; k < pa.size(); ++k) {
        const double moved = (xa[k] - pa[k]).norm();
        ASSERT_LT(moved, gap) << "link " << a << " at t = " << t << " of " << tl;
        tightest = std::max(tightest, moved / gap);
      }
    }
    ++link_cases;
    const double tp = a == b ? 0.0 : fast.pair_time(poses, a, b, gap, dir);
    if (tp <= 0) continue;  // not a pair the checker tests
    const auto pb = world(q, b);
    for (double t = tp / 8; t <= std::min(tp, 2.0); t += tp / 8) {
      const auto xa = world(q + t * dir, a), xb = world(q + t * dir, b);
      for (std::size_t i = 0; i < pa.size(); ++i)
        for (std::size_t j = 0; j < pb.size(); ++j)
          ASSERT_LT(std::abs((xa[i] - xb[j]).norm() - (pa[i] - pb[j]).norm()), gap)
              << "links " << a << ", " << b << " at t = " << t;
    }
    ++pair_cases;
  }
  EXPECT_EQ(link_cases, 600);
  EXPECT_GT(pair_cases, 100);
  EXPECT_GT(tightest, 0.5) << "the bound must be close to the true motion somewhere";
  RecordProperty("tightest", std::to_string(tightest));
}
