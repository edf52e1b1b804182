// The fast layer against FCL on real data: the Panda (collision meshes, SRDF) in
// MotionBenchMaker scenes, 100k random configurations in all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/collision/two_layer_checker.hpp"
#include "fixtures.hpp"
#include "gap_certificates.hpp"
#include "test_support.hpp"

using namespace dmgplace;

namespace {
// The Panda with its SRDF, sphere cover and self-distance tables, built once for the suite.
struct PandaArm {
  RobotModel model;
  std::vector<formats::LinkSphere> spheres;
  std::unique_ptr<runtime::Kinematics> kin;
  std::vector<formats::SelfDistanceTable> tables;
};

const PandaArm& panda_arm() {
  static const PandaArm arm = [] {
    const auto shared = test::shared_datasets();
    PandaArm a;
    a.model = test::read_robot_model(shared / "panda/moveit_resources_panda_description/urdf/panda.urdf",
                                     shared / "panda/panda_moveit_config/config/panda.srdf", {shared / "panda"});
    a.spheres = test::robot_spheres(a.model);
    a.kin = std::make_unique<runtime::Kinematics>(a.model, "panda_link0", "panda_hand");
    a.kin->set_joint_value("panda_finger_joint1", 0.04);
    a.tables = test::self_distance_tables(*a.kin, a.spheres);
    return a;
  }();
  return arm;
}
}  // namespace

TEST(CollisionMbm, FastLayerNeverSaysFreeWhereFclCollidesOnPandaScenes) {
  DMGPLACE_REQUIRE_SHARED();
  auto shared = test::shared_datasets();
  const PandaArm& panda = panda_arm();
  const auto& spheres = panda.spheres;
  const runtime::Kinematics& kin = *panda.kin;
  const auto& tables = panda.tables;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0, 1);
  long total = 0, exact_free = 0, fast_free = 0, full = 0, proven = 0, gap_settled = 0, to_fcl = 0;
  for (auto scene_file :
       {"mbm_problems/bookshelf_small_panda/scene0001.yaml", "mbm_problems/table_pick_panda/scene0001.yaml"}) {
    Scene scene = test::read_scene(shared / scene_file);
    auto sdf = test::analytic_sdf(
        scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.3), Eigen::Vector3d(1.6, 1.2, 1.7)), 0.02, 0.25);
    runtime::SphereFieldChecker fast(kin, spheres, sdf, 0.25);
    fast.set_self_tables(tables);
    runtime::ExactChecker exact(kin, scene);
    runtime::TwoLayerChecker both(fast, exact);
    // As bench-mbm runs it: exact primitives, inner-ball collision proofs, FCL only against the
    // primitives a flagged link's spheres reach.
    runtime::SphereFieldChecker fast_exact = fast;
    fast_exact.set_exact_obstacles(runtime::PrimitiveObstacles::from_scene(scene));
    runtime::TwoLayerChecker both_exact(fast_exact, exact);
    for (int i = 0; i < 50000; ++i) {
      Eigen::VectorXd q(7);
      for (int j = 0; j < 7; ++j) q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
      const bool f = fast.is_free(q);
      const auto e = exact.check(q);
      ++total;
      fast_free += f;
      exact_free += e.free();
      ASSERT_FALSE(f && !e.free()) << scene_file << ": fast layer said free where FCL finds " << e.contact
                                   << " at q = " << q.transpose();
      ASSERT_EQ(both.is_free(q), e.free()) << scene_file;
      ASSERT_FALSE(fast_exact.is_free(q) && !e.free()) << scene_file << " (exact primitives) at q = " << q.transpose();
      ASSERT_EQ(both_exact.is_free(q), e.free()) << scene_file << " (exact primitives) at q = " << q.transpose();
    }
    full += both.counters().exact_full.load();
    proven += both_exact.counters().proven_collisions.load();
    gap_settled += both_exact.counters().exact_gaps.load();
    to_fcl += both_exact.counters().exact_pairs.load();
  }
  // Hull gaps (on by default: link hulls, primitive scenes) settle flagged links and pairs that
  // are apart without FCL; FCL gets the rest, colliding ones included (measured: 5030 settled by
  // gaps, 14326 sent to FCL, of 100k; with the looser spheres before the shrunk cover, 10119 and
  // 14898: the tighter spheres now settle the easy ones themselves).
  EXPECT_GT(gap_settled, to_fcl / 4) << "hull gaps should settle a good share of the flagged queries";
  EXPECT_GT(exact_free, 0);
  // The wrist pairs' tables let the fast layer prove most free configurations free by itself
  // (without them, link5 / link7 spheres overlap in ~80% of configurations and it proved none).
  EXPECT_GT(fast_free, exact_free / 2);
  EXPECT_LT(full, total / 2) << "the sphere layer must settle most environment queries itself";
  EXPECT_GT(proven, (total - exact_free) / 10) << "inner balls should prove a good share of the collisions";
  RecordProperty("configurations", int(total));
  RecordProperty("proven_collisions", int(proven));
  RecordProperty("exact_free", int(exact_free));
  RecordProperty("fast_free", int(fast_free));
  RecordProperty("full_exact_checks", int(full));
}

// The tables' bound is a bound: never above FCL's exact distance of the pair, at random joint
// values (between nodes, off the grid), and not loose by more than the grid allows.
TEST(CollisionMbm, SelfDistanceTablesNeverExceedTheExactDistanceOnThePanda) {
  DMGPLACE_REQUIRE_SHARED();
  const PandaArm& panda = panda_arm();
  const RobotModel& model = panda.model;
  const runtime::Kinematics& kin = *panda.kin;
  const auto& tables = panda.tables;
  ASSERT_FALSE(tables.empty());
  bool wrist = false;
  for (const auto& t : tables)
    wrist |= (model.links[std::size_t(t.link_a)].name == "panda_link5" &&
              model.links[std::size_t(t.link_b)].name == "panda_link7");
  EXPECT_TRUE(wrist) << "the link5 / link7 pair must get a table";
  runtime::ExactChecker exact(kin, Scene{});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& t : tables) {
    double worst_gap = 0, far_gap = 0;
    for (int i = 0; i < 300; ++i) {
      Eigen::VectorXd q(7);
      for (int j = 0; j < 7; ++j) q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
      const double x1 = t.joints[1] >= 0 ? q[kin.chain_slot(t.joints[1])] : 0.0;
      const double bound = t.lower_bound(q[kin.chain_slot(t.joints[0])], x1);
      const double d = exact.link_distance(q, t.link_a, t.link_b);
      ASSERT_LE(bound, d + 1e-9) << model.links[std::size_t(t.link_a)].name << " / "
                                 << model.links[std::size_t(t.link_b)].name << " at q = " << q.transpose();
      // Near contact every node is within the bake's tolerance of exact; farther out a node may
      // hold its coarse cell's bound.
      const double node_loss = 2 * (t.slope[0] + t.slope[1]) * std::max(t.step[0], t.step[1]);
      if (d < test::self_table_defaults().exact_below - node_loss) worst_gap = std::max(worst_gap, d - bound);
      else far_gap = std::max(far_gap, d - bound);
    }
    // Loss is at most slope * step / 2 per joint, plus the nearest node's own change...
    EXPECT_LT(worst_gap, 2 * (t.slope[0] + t.slope[1]) * std::max(t.step[0], t.step[1]) +
                             test::self_table_defaults().tolerance + 1e-6);
    // ... and far from contact, what the coarse lattice's Lipschitz bound loses across a cell.
    const double stride = test::self_table_defaults().coarse_stride;
    EXPECT_LT(far_gap, (2 + stride) * (t.slope[0] + t.slope[1]) * std::max(t.step[0], t.step[1]) + 1e-6);
  }
}

// link_distance_within, from where the links were closest a table step away: never above FCL's
// exact distance, never more than its tolerance below, and on some pairs settled by the convex
// hulls and the two nearby triangles (a cheap answer is the hulls' gap, below exact).
TEST(CollisionMbm, LinkDistanceWithinIsAProvenBoundWithinItsTolerance) {
  DMGPLACE_REQUIRE_SHARED();
  const PandaArm& panda = panda_arm();
  const runtime::Kinematics& kin = *panda.kin;
  runtime::ExactChecker exact(kin, Scene{});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const double tolerance = 2e-4;
  int cheap = 0, asked = 0;
  for (const auto& t : panda.tables)
    for (int i = 0; i < 150; ++i) {
      Eigen::VectorXd q(7);
      for (int j = 0; j < 7; ++j) q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
      runtime::LinkWitness near;
      exact.link_distance(q, t.link_a, t.link_b, &near);
      Eigen::VectorXd step = q;
      for (int k = 0; k < 2; ++k)
        if (t.joints[std::size_t(k)] >= 0) {
          const int slot = kin.chain_slot(t.joints[std::size_t(k)]);
          step[slot] = std::clamp(q[slot] + (u(rng) < 0.5 ? -1 : 1) * t.step[std::size_t(k)], kin.lower()[slot],
                                  kin.upper()[slot]);
        }
      const double d = exact.link_distance(step, t.link_a, t.link_b);
      const double within = exact.link_distance_within(step, t.link_a, t.link_b, tolerance, {near});
      ASSERT_LE(within, d + 1e-12) << "at q = " << step.transpose();
      ASSERT_GE(within, d - tolerance - 1e-12) << "at q = " << step.transpose();
      cheap += within < d - 1e-9;
      ++asked;
    }
  EXPECT_GT(cheap, 0) << "no answer from the hulls in " << asked;
  RecordProperty("settled_by_hulls", cheap);
  RecordProperty("asked", asked);
}

// With no tolerance, link_distance_within is FCL's exact distance, however far the nearby
// witness is (FCL only starts from the pair it names), and the witness it hands on names two
// triangles exactly that far apart at q: the pair the next node along a table's row starts from.
TEST(CollisionMbm, LinkDistanceStartedFromANearbyPairIsTheExactDistance) {
  DMGPLACE_REQUIRE_SHARED();
  const PandaArm& panda = panda_arm();
  const runtime::Kinematics& kin = *panda.kin;
  runtime::ExactChecker exact(kin, Scene{});
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  int started = 0;
  for (const auto& t : panda.tables)
    for (int i = 0; i < 100; ++i) {
      Eigen::VectorXd q(7), far(7);
      for (int j = 0; j < 7; ++j) {
        q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
        far[j] = std::clamp(q[j] + (u(rng) - 0.5) * (i % 2 ? 0.05 : 1.0), kin.lower()[j], kin.upper()[j]);
      }
      runtime::LinkWitness near, handed;
      exact.link_distance(far, t.link_a, t.link_b, &near);
      const double d = exact.link_distance(q, t.link_a, t.link_b);
      const double from_near = exact.link_distance_within(q, t.link_a, t.link_b, 0.0, {near}, &handed);
      ASSERT_NEAR(from_near, d, 1e-12) << "at q = " << q.transpose();
      started += near.part_a >= 0;
      if (d > 0) {
        ASSERT_GE(handed.part_a, 0);
        runtime::LinkWitness again;
        // The handed pair alone, as the only witness: it is at d, so FCL finds nothing closer.
        EXPECT_NEAR(exact.link_distance_within(q, t.link_a, t.link_b, 0.0, {handed}, &again), d, 1e-12);
        EXPECT_EQ(again.tri_a, handed.tri_a);
        EXPECT_EQ(again.tri_b, handed.tri_b);
      }
    }
  EXPECT_GT(started, 0);
}

// The tables' slopes bound how fast the pair's exact distance changes with the table's joints:
// the Lipschitz bound certified checks (the self pass's table limit) and span lane checks
// (LaneMotion::table_travel) widen a table's bound by. And not loosely everywhere: on some table
// some step's change comes within a factor of two of it, so slopes half as large fail here.
TEST(CollisionMbm, SelfDistanceTableSlopesBoundHowFastTheExactDistanceChanges) {
  DMGPLACE_REQUIRE_SHARED();
  const PandaArm& panda = panda_arm();
  const runtime::Kinematics& kin = *panda.kin;
  const RobotModel& model = panda.model;
  runtime::ExactChecker exact(kin, Scene{});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> n(0, 1);
  ASSERT_FALSE(panda.tables.empty());
  double tightest_of_all = 0;
  for (const auto& t : panda.tables) {
    const std::string name = model.links[std::size_t(t.link_a)].name + " / " + model.links[std::size_t(t.link_b)].name;
    double tightest = 0;
    for (int i = 0; i < 400; ++i) {
      Eigen::VectorXd q(7);
      for (int j = 0; j < 7; ++j) q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
      // One joint at a time (the first, the second, then both), so neither joint's slope hides
      // behind the other's.
      Eigen::VectorXd moved = q;
      double budget = 0;
      for (int k = 0; k < 2; ++k) {
        if (t.joints[std::size_t(k)] < 0 || i % 3 == 1 - k) continue;
        const int slot = kin.chain_slot(t.joints[std::size_t(k)]);
        moved[slot] = std::clamp(q[slot] + 0.05 * n(rng), kin.lower()[slot], kin.upper()[slot]);
        budget += t.slope[std::size_t(k)] * std::abs(moved[slot] - q[slot]);
      }
      // Overlapping meshes count as 0 apart: the clearance the bound speaks of.
      const double before = std::max(0.0, exact.link_distance(q, t.link_a, t.link_b));
      const double after = std::max(0.0, exact.link_distance(moved, t.link_a, t.link_b));
      ASSERT_LE(std::abs(after - before), budget + 1e-9)
          << name << " from q = " << q.transpose() << " to " << moved.transpose();
      if (budget > 1e-4) tightest = std::max(tightest, std::abs(after - before) / budget);
    }
    EXPECT_GT(tightest, 0.2) << name << ": every change far below the slopes' bound";
    tightest_of_all = std::max(tightest_of_all, tightest);
    RecordProperty(name + " tightest", std::to_string(tightest));
  }
  EXPECT_GT(tightest_of_all, 0.5) << "every change far below the slopes' bound: slopes too small would pass";
}

// The Panda's link meshes in both MotionBenchMaker scenes: proven clearances (the meshes' convex
// hulls against the primitives and each other) certify flagged states, and every certified
// stretch is free.
TEST(CollisionMbm, ExactGapCertificatesKeepEveryPandaStateFree) {
  DMGPLACE_REQUIRE_SHARED();
  const auto shared = test::shared_datasets();
  const PandaArm& panda = panda_arm();
  for (auto scene_file :
       {"mbm_problems/bookshelf_small_panda/scene0001.yaml", "mbm_problems/table_pick_panda/scene0001.yaml"}) {
    const Scene scene = test::read_scene(shared / scene_file);
    runtime::SphereFieldChecker fast(
        *panda.kin, panda.spheres,
        test::analytic_sdf(
            scene, Eigen::AlignedBox3d(Eigen::Vector3d(-1.2, -1.2, -0.3), Eigen::Vector3d(1.6, 1.2, 1.7)), 0.02, 0.25),
        0.25);
    fast.set_self_tables(panda.tables);
    fast.set_exact_obstacles(runtime::PrimitiveObstacles::from_scene(scene));
    const runtime::ExactChecker exact(*panda.kin, scene);
    EXPECT_TRUE(exact.gaps_are_cheap()) << "link meshes with their hulls: on by default";
    runtime::TwoLayerChecker both(fast, exact);
    both.set_exact_gaps(true);
    double longest = 0;
    const int walked = test::walk_gap_certificates(both, exact, 1500, 23, &longest);
    EXPECT_GT(walked, 50) << scene_file;
    EXPECT_GT(longest, 0.005) << scene_file;
  }
}

// The Panda's SRDF "ready" pose (the MBM problems' start) is free: exactly, on its own and in both
// MBM scenes, and the fast layer with the self-distance tables proves it free by itself in
// free space (no FCL call), which it could not while the wrist spheres overlapped.
TEST(CollisionMbm, PandaReadyPoseIsCollisionFree) {
  DMGPLACE_REQUIRE_SHARED();
  const auto shared = test::shared_datasets();
  const PandaArm& panda = panda_arm();
  const runtime::Kinematics& kin = *panda.kin;
  Eigen::VectorXd ready(7);
  ready << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  const runtime::ExactChecker alone(kin, Scene{});
  EXPECT_TRUE(alone.is_free(ready)) << alone.check(ready).contact;
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1.2, -1.2, -0.3), Eigen::Vector3d(1.6, 1.2, 1.7));
  runtime::SphereFieldChecker empty(kin, panda.spheres, test::analytic_sdf(Scene{}, box, 0.02, 0.25), 0.25);
  empty.set_self_tables(panda.tables);
  EXPECT_TRUE(empty.check(ready).self_free) << "the self-distance tables must settle the wrist at the ready pose";
  for (auto scene_file :
       {"mbm_problems/bookshelf_small_panda/scene0001.yaml", "mbm_problems/table_pick_panda/scene0001.yaml"}) {
    const Scene scene = test::read_scene(shared / scene_file);
    runtime::SphereFieldChecker fast(kin, panda.spheres, test::analytic_sdf(scene, box, 0.02, 0.25), 0.25);
    fast.set_self_tables(panda.tables);
    const runtime::ExactChecker exact(kin, scene);
    EXPECT_TRUE(exact.is_free(ready)) << scene_file << ": " << exact.check(ready).contact;
    EXPECT_TRUE(runtime::TwoLayerChecker(fast, exact).is_free(ready)) << scene_file;
  }
}

// A hull contains its mesh, so the gap measured between two links' hulls never exceeds the links'
// true mesh distance (FCL), over random configurations of every self-checked pair.
TEST(CollisionMbm, PandaHullGapsNeverExceedTheMeshDistance) {
  DMGPLACE_REQUIRE_SHARED();
  const PandaArm& panda = panda_arm();
  const runtime::ExactChecker exact(*panda.kin, Scene{});
  std::mt19937_64 rng(31);
  std::vector<Eigen::Isometry3d> poses;
  int positive = 0, checked = 0;
  const int links = int(panda.model.links.size());
  for (int n = 0; n < 200; ++n) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(panda.kin->dof());
    std::uniform_real_distribution<double> u(0, 1);
    for (int j = 0; j < q.size(); ++j)
      q[j] = panda.kin->lower()[j] + u(rng) * (panda.kin->upper()[j] - panda.kin->lower()[j]);
    panda.kin->link_poses(q, poses);
    for (int a = 0; a < links; ++a)
      for (int b = a + 2; b < links; ++b) {
        if (panda.model.links[std::size_t(a)].collision.empty() || panda.model.links[std::size_t(b)].collision.empty())
          continue;
        const double gap = exact.link_pair_gap(poses, a, b);
        const double truth = exact.link_distance(q, a, b);
        ASSERT_LE(gap, truth + 1e-9) << panda.model.links[std::size_t(a)].name << " / "
                                     << panda.model.links[std::size_t(b)].name;
        positive += gap > 0;
        ++checked;
      }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(positive, checked / 2) << "hull gaps prove most separations";
}
