// The lanes: 8 configurations per call (lane forward kinematics, free_lanes, free_lanes_along,
// motion_bounds), on both SIMD paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <random>
#include <string>

#include "collision_fixtures.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"
#include "lane_rounds.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;
using test::lane_rounds_on_every_path;
using test::random_q;

// Issue 20: 8 configurations per call. Lane forward kinematics equals the scalar one, on the
// AVX2 path (where the CPU has it) and on the portable one, with the base at the root and not.
TEST(Lanes, ForwardKinematicsEqualsTheScalarOneOnEveryPath) {
  Arm arm = built_in_arm();
  for (const char* base : {"dmgarm_link0", "dmgarm_link2"}) {
    Kinematics kin(arm.model, base, "dmgarm_tcp");
    kin.set_joint_value("dmgarm_finger_joint1", 0.021);  // a mimic follows it
    lane_rounds_on_every_path(
        kin, 3, 50, [](int, Eigen::VectorXd&) {},
        [&](const std::vector<Eigen::VectorXd>& qs, const double* const* ptr) {
          LinkPoseLanesD in_lanes;
          kin.lanes().link_poses(ptr, in_lanes);
          std::vector<Eigen::Isometry3d> poses;
          for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) {
            kin.link_poses(qs[std::size_t(k)], poses);
            for (std::size_t l = 0; l < poses.size(); ++l)
              for (int e = 0; e < 12; ++e) {
                const double want = e < 9 ? poses[l].linear()(e / 3, e % 3) : poses[l].translation()[e - 9];
                ASSERT_NEAR(in_lanes.pose[l][std::size_t(e)][std::size_t(k)], want, 1e-12)
                    << base << " " << to_string(simd_path()) << " link " << l << " element " << e;
              }
          }
        });
  }
}

// The float lane check (what the lane sphere check runs on) stays within Kinematics::float_pose_error
// of the double poses, for points within `reach` of their link: on every path, the base at the
// root and not, prismatic mimic fingers set. And the bound is tight enough to be of use.
TEST(Lanes, FloatForwardKinematicsStaysWithinItsErrorBound) {
  Arm arm = built_in_arm();
  const double reach = 1.5;
  for (const char* base : {"dmgarm_link0", "dmgarm_link2"}) {
    Kinematics kin(arm.model, base, "dmgarm_tcp");
    kin.set_joint_value("dmgarm_finger_joint1", 0.021);
    const double bound = kin.lanes().float_pose_error(reach);
    EXPECT_GT(bound, 0.0);
    EXPECT_LT(bound, 1e-4) << "a bound this loose would cost the lane check its proofs";
    double worst = 0;
    auto wide_angles = [](int round, Eigen::VectorXd& q) {
      if (round % 4 == 0) q *= 40.0;  // sin and cos far from the first turn
    };
    lane_rounds_on_every_path(
        kin, 5, 200, wide_angles, [&](const std::vector<Eigen::VectorXd>& qs, const double* const* ptr) {
          LinkPoseLanesF in_lanes;
          kin.lanes().link_poses(ptr, in_lanes);
          std::vector<Eigen::Isometry3d> poses;
          for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) {
            kin.link_poses(qs[std::size_t(k)], poses);
            for (std::size_t l = 0; l < poses.size(); ++l)
              for (int axis = 0; axis < 7; ++axis) {
                Eigen::Vector3d p = Eigen::Vector3d::Zero();
                if (axis < 6) p[axis % 3] = axis < 3 ? reach : -reach;
                const auto& e = in_lanes.pose[l];
                auto at = [&](int i) { return e[std::size_t(i)][std::size_t(k)]; };
                Eigen::Vector3d got;
                for (int r = 0; r < 3; ++r)
                  got[r] = double(at(3 * r) * float(p.x()) + at(3 * r + 1) * float(p.y()) +
                                  at(3 * r + 2) * float(p.z()) + at(9 + r));
                const double err = (got - poses[l] * p).norm();
                worst = std::max(worst, err);
                ASSERT_LE(err, bound) << base << " " << to_string(simd_path()) << " link " << l << " point " << axis;
              }
          }
        });
    RecordProperty(std::string("worst_over_bound_") + base, std::to_string(worst / bound));
    std::cout << base << ": worst float error " << worst << " m, bound " << bound << " m\n";
  }
}

// A lane the lane check proves free is free for the scalar fast layer (hence for FCL, by the test
// above), and the lane check proves most of what the scalar layer proves: on both paths, with the
// self-distance tables, with a held object, and with the scene's exact primitives (which the lane check
// trusts outside the grid too, so there FCL is the judge).
TEST(Lanes, FreeLanesAreFreeForTheScalarLayerAndFclAndMostAreProven) {
  ShelfWorld w;
  SphereFieldChecker fast(w.kin, w.arm.spheres, w.sdf, 0.3);
  fast.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  const int tcp = w.arm.model.link_index("dmgarm_tcp");
  AttachedSpheres object;
  object.link = tcp;
  object.centers = {Eigen::Vector3d(0, 0, 0.02), Eigen::Vector3d(0, 0, 0.06)};
  object.radii = {0.025, 0.025};
  object.touching_links = {w.arm.model.link_index("dmgarm_leftfinger"), w.arm.model.link_index("dmgarm_rightfinger")};
  const SphereFieldChecker held = fast.with_attached(object);
  SphereFieldChecker primitives = fast;
  primitives.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  ASSERT_TRUE(primitives.free_lanes(std::array<const double*, 1>{w.kin.lower().data()}.data(), 1) <= 1u);
  ExactChecker exact(w.kin, w.scene);
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SphereFieldChecker* checker : std::initializer_list<const SphereFieldChecker*>{&fast, &held, &primitives})
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
      force_simd_path(path);
      std::mt19937_64 rng(11);
      int scalar_free = 0, lanes_free = 0;
      for (int round = 0; round < 1500; ++round) {
        std::vector<Eigen::VectorXd> qs;
        const double* ptr[LinkPoseLanesD::kLanes];
        for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) qs.push_back(random_q(w.kin, rng));
        for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
        const int count = 1 + round % LinkPoseLanesD::kLanes;  // partial lane checks too
        const std::uint32_t mask = checker->free_lanes(ptr, count);
        EXPECT_EQ(mask >> count, 0u);
        for (int k = 0; k < count; ++k) {
          const bool scalar = checker->check(qs[std::size_t(k)]).free(), in_lane = mask >> k & 1u;
          scalar_free += scalar;
          lanes_free += in_lane;
          if (checker != &primitives) {
            ASSERT_FALSE(in_lane && !scalar)
                << "lane check said free where the scalar layer does not: " << qs[std::size_t(k)].transpose();
          }
          if (checker != &held) {
            ASSERT_FALSE(in_lane && !exact.is_free(qs[std::size_t(k)])) << qs[std::size_t(k)].transpose();
          }
        }
      }
      EXPECT_GT(scalar_free, 100);
      EXPECT_GE(lanes_free, scalar_free * 9 / 10) << "the lane check proves " << lanes_free << " of " << scalar_free;
    }
}

// The lane check works in floats, forward kinematics included: its rounding margin must hold exactly where
// it matters, at the edge of "free". With the scene's exact primitives the scalar layer's verdict
// on the scene is continuous (every sphere's exact distance), so bisecting between a configuration
// it proves free and one where only the scene stops it gives one within 1e-12 of that edge on the
// blocked side; there the lane check must not say free. (Float rounding is ~1e-7 m: with the margin
// set to 0 this fails. The field's nearest-node bound jumps between nodes, so its edges are no
// test of rounding.)
TEST(Lanes, FloatLanesStayConservativeAtTheEdgeOfTheScene) {
  ShelfWorld w;
  SphereFieldChecker checker(w.kin, w.arm.spheres, w.sdf, 0.3);
  checker.set_self_tables(test::self_distance_tables(w.kin, w.arm.spheres));
  checker.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    force_simd_path(path);
    std::mt19937_64 rng(5);
    for (int round = 0; round < 60; ++round) {
      std::vector<Eigen::VectorXd> qs;
      while (int(qs.size()) < LinkPoseLanesD::kLanes) {
        Eigen::VectorXd a = random_q(w.kin, rng), b = random_q(w.kin, rng);
        if (!checker.is_free(a) || checker.is_free(b)) continue;
        for (int i = 0; i < 45; ++i) {  // a stays free, b not
          const Eigen::VectorXd m = 0.5 * (a + b);
          (checker.is_free(m) ? a : b) = m;
        }
        const SphereCheck edge = checker.check(b);
        if (!edge.environment_free && edge.self_free) qs.push_back(b);
      }
      const double* ptr[LinkPoseLanesD::kLanes];
      for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
      ASSERT_EQ(checker.free_lanes(ptr), 0u) << "the lane check said free just past the scene's edge";
    }
  }
}

// The float margin is the kinematics' as they are when a lane check runs: setting a joint outside the
// chain moves the float poses' error bound (a prismatic joint's offset enters it; the fingers set
// 2 m out, as a long lift outside the chain would be, make it the largest), and a checker built
// before follows it, as one built afresh has it grow. (The two differ: the fresh one carries the
// fingers 2 m from the frame they ride, Kinematics::lane_frame; the one built before, whose
// offsets are stale, places them from their own links.)
TEST(Lanes, LaneMarginFollowsJointsSetOutsideTheChain) {
  ShelfWorld w;
  SphereFieldChecker before(w.kin, w.arm.spheres, w.sdf, 0.3);
  before.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  const double was = before.lane_margin();
  w.kin.set_joint_value("dmgarm_finger_joint1", 2.0);
  SphereFieldChecker fresh(w.kin, w.arm.spheres, w.sdf, 0.3);
  fresh.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
  EXPECT_GT(fresh.lane_margin(), was) << "the fingers' value does not enter the bound: nothing to follow";
  EXPECT_GT(before.lane_margin(), was) << "a checker built before kept its margin";
}

// A checker built before a joint outside the chain is set places its bodies from their own links
// (the lane frames it carried them into moved): its free lanes stay free for FCL with the
// fingers as they are now, and it proves as much as a checker built afresh. The fingers go from
// closed to 0.3 m out (as a lift outside the chain would move a link), so a lane check still placing
// them closed says free where they now hit.
TEST(Lanes, FreeLanesFollowJointsSetAfterTheCheckerWasBuilt) {
  ShelfWorld w;
  w.kin.set_joint_value("dmgarm_finger_joint1", 0.3);
  const auto tables = test::self_distance_tables(w.kin, w.arm.spheres);  // as the fingers end
  auto checker = [&] {
    SphereFieldChecker c(w.kin, w.arm.spheres, w.sdf, 0.3);
    c.set_self_tables(tables);
    c.set_exact_obstacles(PrimitiveObstacles::from_scene(w.scene));
    return c;
  };
  w.kin.set_joint_value("dmgarm_finger_joint1", 0.0);
  const SphereFieldChecker before = checker();
  w.kin.set_joint_value("dmgarm_finger_joint1", 0.3);
  const SphereFieldChecker fresh = checker();
  ExactChecker exact(w.kin, w.scene);
  int before_free[2] = {0, 0}, fresh_free[2] = {0, 0};  // per path: portable, AVX2
  lane_rounds_on_every_path(w.kin, 21, 800, [&](const std::vector<Eigen::VectorXd>& qs, const double* const* ptr) {
    const int at = simd_path() == SimdPath::Avx2;
    const std::uint32_t a = before.free_lanes(ptr), b = fresh.free_lanes(ptr);
    before_free[at] += __builtin_popcount(a);
    fresh_free[at] += __builtin_popcount(b);
    for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) {
      if (!((a | b) >> k & 1u)) continue;
      ASSERT_TRUE(exact.is_free(qs[std::size_t(k)])) << to_string(simd_path()) << " " << qs[std::size_t(k)].transpose();
    }
  });
  for (int at = 0; at < 2; ++at) {
    EXPECT_GT(fresh_free[at], 1000);
    EXPECT_GE(before_free[at], fresh_free[at] * 99 / 100) << "path " << at;
    EXPECT_GE(fresh_free[at], before_free[at] * 99 / 100) << "path " << at;
    std::cout << (at ? "avx2" : "portable") << ": " << before_free[at] << " free by the checker built before, "
              << fresh_free[at] << " afresh\n";
  }
}

// A lane proven along a direction proves every state within its reach: each one sampled 2.5 mrad
// apart is free for the scalar layer (FCL with the scene's exact primitives, which the lane check
// trusts outside the grid too). The test finds lanes whose center alone is free but some state
// within reach is not, so a lane check that widened nothing would fail it; reach 0 is free_lanes.
TEST(Lanes, LanesAlongADirectionProveEveryStateWithinTheirReach) {
  const AlongCheckers c(true);
  const ShelfWorld& w = c.w;
  int near_misses = 0;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SphereFieldChecker* checker : c.all())
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
      force_simd_path(path);
      auto judge = [&](const Eigen::VectorXd& q) { return c.judge(checker, q); };
      std::mt19937_64 rng(17);
      std::normal_distribution<double> n(0, 1);
      int proven = 0;
      for (int round = 0; round < 160; ++round) {
        const RandomLanes lanes(w.kin, rng, n);
        const auto& qs = lanes.qs;
        const auto& ptr = lanes.ptr;
        const auto& u = lanes.u;
        const double reach = round % 2 ? 0.08 : 0.03;
        const std::uint32_t alone = checker->free_lanes(ptr),
                            along = checker->free_lanes_along(ptr, LinkPoseLanesD::kLanes, u, reach);
        ASSERT_EQ(checker->free_lanes_along(ptr, LinkPoseLanesD::kLanes, u, 0.0), alone);
        ASSERT_EQ(along & ~alone, 0u) << "proven along but not alone";
        for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) {
          if (!(alone >> k & 1u)) continue;
          bool all_free = true;
          for (double t = -reach; t <= reach + 1e-12 && all_free; t += 0.0025)
            all_free = judge(qs[std::size_t(k)] + t * u);
          near_misses += !all_free;
          if (!(along >> k & 1u)) continue;
          ++proven;
          ASSERT_TRUE(all_free) << "lane " << k << " proven for " << reach << " along " << u.transpose() << " from "
                                << qs[std::size_t(k)].transpose();
        }
      }
      EXPECT_GT(proven, 60) << to_string(path);
    }
  EXPECT_GT(near_misses, 10) << "no lane was free alone and blocked within reach: the test cannot tell";
  RecordProperty("near_misses", near_misses);
}

// free_lanes_along's widening bounds every motion it covers: over +-reach along the direction,
// no point of a body's spheres (the held object's too) moves farther than its bound, and no two
// points of a checked pair change their distance by more than the pair's, lane by lane. The
// bounds are tight where the lanes' own lever arms are used: the largest ratio of motion to bound
// comes near 1 (so a bound a fifth too small fails here), where the static bound alone stays far
// below.
TEST(Lanes, MotionBoundsCoverEveryPointOfEachBodyAndPair) {
  const AlongCheckers c(true);
  const ShelfWorld& w = c.w;
  std::mt19937_64 rng(29);
  std::normal_distribution<double> n(0, 1);
  // Points of a link's spheres (held object's, for the attached body): centers and six extremes.
  auto points = [&](int link, bool attached) {
    std::vector<Eigen::Vector3d> out;
    auto add = [&](const Eigen::Vector3d& center, double r) {
      out.push_back(center);
      for (int i = 0; i < 3; ++i)
        for (const double sign : {-1.0, 1.0}) out.push_back(center + sign * r * Eigen::Vector3d::Unit(i));
    };
    if (attached)
      for (std::size_t i = 0; i < c.object.centers.size(); ++i) add(c.object.centers[i], c.object.radii[i]);
    else
      for (const auto& s : w.arm.spheres)
        if (s.link == link) add(s.center, s.radius);
    return out;
  };
  double worst = 0;
  int bodies = 0, pairs = 0, lane_checks = 0;
  std::vector<Eigen::Isometry3d> p0, pt;
  for (int round = 0; round < 40; ++round) {
    const RandomLanes lanes(w.kin, rng, n);
    const auto& qs = lanes.qs;
    const auto& ptr = lanes.ptr;
    const auto& u = lanes.u;
    const double reach = std::array{0.01, 0.04, 0.12}[std::size_t(round % 3)];
    const auto bounds = c.held.motion_bounds(ptr, LinkPoseLanesD::kLanes, u, reach);
    if (bounds.empty()) continue;
    ++lane_checks;
    for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) {
      w.kin.link_poses(qs[std::size_t(k)], p0);
      for (int step = -10; step <= 10; ++step) {
        if (step == 0) continue;
        w.kin.link_poses(qs[std::size_t(k)] + (reach * step / 10.0) * u, pt);
        for (const auto& b : bounds) {
          const double bound = b.metres[std::size_t(k)];
          const bool held_a = b.attached && (b.link_b < 0 || b.link_a == c.object.link);
          const auto pa = points(b.link_a, held_a);
          double moved = 0;
          if (b.link_b < 0) {
            for (const auto& x : pa)
              moved = std::max(moved, (pt[std::size_t(b.link_a)] * x - p0[std::size_t(b.link_a)] * x).norm());
            bodies += step == 10;
          } else {
            const auto pb = points(b.link_b, b.attached && !held_a);
            for (const auto& x : pa)
              for (const auto& y : pb) {
                const double d0 = (p0[std::size_t(b.link_a)] * x - p0[std::size_t(b.link_b)] * y).norm();
                const double d1 = (pt[std::size_t(b.link_a)] * x - pt[std::size_t(b.link_b)] * y).norm();
                moved = std::max(moved, std::abs(d1 - d0));
              }
            pairs += step == 10;
          }
          ASSERT_LE(moved, bound + 1e-9) << "link " << b.link_a
                                         << (b.link_b >= 0 ? " with " + std::to_string(b.link_b) : "") << ", lane " << k
                                         << ", reach " << reach << ", step " << step;
          if (bound > 0) worst = std::max(worst, moved / bound);
        }
      }
    }
  }
  EXPECT_GT(lane_checks, 30);
  EXPECT_GT(bodies, 1000);
  EXPECT_GT(pairs, 1000);
  EXPECT_GT(worst, 0.85) << "the bounds are loose everywhere: a bound too small would pass";
  RecordProperty("largest_motion_over_bound", std::to_string(worst));
}

// Lanes lined up short of a collision, heading for it, most within one reach of it: a lane whose
// reach takes in the collision must not be proven, however clear the lane's own state. Many such
// lanes are proven free alone (free_lanes), so only the widening stands between them and a wrong
// proof (with no widening this fails at once).
TEST(Lanes, LanesHeadingForACollisionAreNotProvenPastIt) {
  const AlongCheckers c(true);
  const ShelfWorld& w = c.w;
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SphereFieldChecker* checker : c.all())
    for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
      force_simd_path(path);
      auto judge = [&](const Eigen::VectorXd& q) { return c.sphere_judge(checker, q); };
      std::mt19937_64 rng(23);
      std::normal_distribution<double> n(0, 1);
      int cases = 0, free_alone = 0;
      for (int attempt = 0; attempt < 4000 && cases < 20; ++attempt) {
        const Eigen::VectorXd q = random_q(w.kin, rng);
        Eigen::VectorXd u(w.kin.dof());
        for (int i = 0; i < u.size(); ++i) u[i] = n(rng);
        u.normalize();
        if (!judge(q)) continue;
        double hit = -1;  // the first blocked state along u, 2.5 mrad apart
        for (double t = 0.0025; t <= 0.4 && hit < 0; t += 0.0025)
          if (!judge(q + t * u)) hit = t;
        if (hit < 0.05) continue;
        ++cases;
        const double reach = std::min(0.04, hit / 2);
        auto short_of = [&](int k) { return reach * (0.15 + 0.125 * k); };  // 0.15 .. 1.025 reaches short of it
        std::vector<Eigen::VectorXd> qs;
        const double* ptr[LinkPoseLanesD::kLanes];
        for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) qs.push_back(q + (hit - short_of(k)) * u);
        for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
        const std::uint32_t along = checker->free_lanes_along(ptr, LinkPoseLanesD::kLanes, u, reach);
        const std::uint32_t alone = checker->free_lanes(ptr);
        for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) {
          if (!(short_of(k) < reach)) continue;
          free_alone += alone >> k & 1u;
          ASSERT_FALSE(along >> k & 1u) << to_string(path) << ": lane " << k << " proven " << short_of(k) / reach
                                        << " reaches short of a collision";
        }
      }
      EXPECT_GE(cases, 20) << to_string(path);
      EXPECT_GT(free_alone, 3) << to_string(path) << ": the lanes are not free alone, the test cannot tell";
    }
}
