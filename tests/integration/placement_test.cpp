// The placement planner end to end on the built-in data: the cabinet, dmgarm and the bottle,
// baked through the CLI once for the suite, then driven through the C++ API.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <thread>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"
#include "placement_fixture.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
using test::side_grasp;
using test::top_grasp;
using test::vec;
class Placement : public test::PlacementFixture {};
}  // namespace

TEST_F(Placement, BlockingGraspIsPlacedOnlyAfterRegrasp) {
  PlacementQuery qr = query(top_grasp());
  qr.volume = deep_lower_shelf();
  qr.variant = PlacementVariant::NoRegrasp;
  const PlacementResult none = solve(qr, 1500);
  EXPECT_FALSE(none.solved());
  EXPECT_NE(none.reason.find("no placement found"), std::string::npos) << none.reason;

  qr.variant = PlacementVariant::Full;
  const PlacementResult full = solve(qr, 4000, true);
  ASSERT_TRUE(full.solved()) << full.reason;
  const PlacementSolution& s = full.best();
  ASSERT_FALSE(s.in_hand.empty());
  // The in-hand sequence is a chain of grasp-graph moves from g0's state to g*'s.
  EXPECT_EQ(s.in_hand.front().from_state, full.initial_state);
  for (std::size_t i = 1; i < s.in_hand.size(); ++i) EXPECT_EQ(s.in_hand[i].from_state, s.in_hand[i - 1].to_state);
  EXPECT_EQ(s.in_hand.back().to_state, s.grasp_state);
  EXPECT_TRUE(deep_lower_shelf().contains(s.pose * world_->object().mass.com - Eigen::Vector3d(0, 0, 0.05)) ||
              s.pose.translation().z() < 0.72);
}

TEST_F(Placement, EveryPublishedSolutionIsStableFreeAndImproving) {
  PlacementQuery qr = query(side_grasp());
  const PlacementResult r = solve(qr, 1500);
  ASSERT_TRUE(r.solved()) << r.reason;
  const Kinematics& kin = world_->kinematics();
  const auto& env = world_->env();
  for (std::size_t k = 0; k < r.improvements.size(); ++k) {
    const PlacementSolution& s = r.improvements[k];
    SCOPED_TRACE("improvement " + std::to_string(k));
    if (k > 0) {
      const auto& prev = r.improvements[k - 1];
      const bool up = s.objective > prev.objective + qr.options.tie_tolerance;
      const bool tie =
          std::abs(s.objective - prev.objective) <= qr.options.tie_tolerance && s.in_hand.size() < prev.in_hand.size();
      EXPECT_TRUE(up || tie) << prev.objective << " -> " << s.objective;
      EXPECT_GE(s.time, prev.time);
    }
    // Starts at q0; every segment collision-free for the exact layer at the checking resolution.
    ASSERT_GE(s.path.size(), 2u);
    EXPECT_LT((vec(s.path.front()) - qr.q0).norm(), 1e-9);
    const ExactChecker exact = world_->grasp_exact(s.grasp, s.opening);
    for (std::size_t i = 1; i < s.path.size(); ++i)
      ASSERT_TRUE(exact.segment_free(vec(s.path[i - 1]), vec(s.path[i]), qr.options.motion_resolution))
          << "segment " << i;
    // The retreat starts where the path ends and every segment is free for the exact layer with
    // the object released at its placement.
    if (!s.retreat.empty()) {
      Eigen::Isometry3d up = s.pose;
      up.translation().z() += qr.options.lift;
      const ExactChecker released = world_->released_exact(up, s.release_opening);
      for (std::size_t i = 1; i < s.retreat.size(); ++i)
        ASSERT_TRUE(released.segment_free(vec(s.retreat[i - 1]), vec(s.retreat[i]), qr.options.motion_resolution))
            << "retreat " << i;
      // The fingers let go by release_clearance each, or (where that finds no retreat) by the
      // gripper's contact tolerance, never beyond the gripper's maximum.
      const auto& gripper = world_->object().dmg.gripper;
      const double wide = std::min(gripper.max_opening, s.opening + 2 * qr.options.release_clearance);
      const double narrow = std::min(wide, s.opening + 2 * gripper.contact_tolerance);
      EXPECT_TRUE(s.release_opening == wide || s.release_opening == narrow) << s.release_opening;
      EXPECT_GT(s.release_opening, s.opening);
    }
    // The arm at the end of the path holds the object just above its resting pose.
    const Eigen::Isometry3d held = kin.tip_pose(vec(s.path.back())) * s.grasp.inverse();
    EXPECT_LT((held.translation() - s.pose.translation() - Eigen::Vector3d(0, 0, qr.options.lift)).norm(), 1e-3);
    EXPECT_LT(Eigen::AngleAxisd(held.linear() * s.pose.linear().transpose()).angle(), 1e-2);
    // Stable: the face's polygon lies on the region's surface, over supported cells, COM too.
    const auto& region = env.regions.at(std::size_t(s.region));
    const auto& face = world_->object().placement.faces.at(std::size_t(s.face));
    auto supported = [&](const Eigen::Vector3d& p) {
      const Eigen::Vector2d u = (p.head<2>() - region.origin) / region.resolution;
      const int i = int(std::floor(u.x())), j = int(std::floor(u.y()));
      return i >= 0 && j >= 0 && i < region.width && j < region.depth &&
             region.mask[std::size_t(i) + std::size_t(region.width) * std::size_t(j)];
    };
    for (const auto& v : face.polygon) {
      const Eigen::Vector3d w = s.pose * v;
      EXPECT_NEAR(w.z(), region.height, 1e-6);
      EXPECT_TRUE(supported(w));
    }
    EXPECT_TRUE(supported(s.pose * world_->object().mass.com));
    Eigen::Isometry3d lifted = s.pose;
    lifted.translation().z() += qr.options.lift;
    EXPECT_TRUE(world_->exact().mesh_free(world_->object_mesh(), lifted));
    // The retreat leaves from the placement configuration.
    ASSERT_FALSE(s.retreat.empty());
    EXPECT_LT((vec(s.retreat.front()) - vec(s.path.back())).norm(), 1e-9);
    // ... and is a motion back to the retreat configuration (q0 here).
    EXPECT_LT((vec(s.retreat.back()) - qr.q0).norm(), 1e-9);
  }
}

// The retreat motion goes where the query says; a retreat configuration that cannot be one is
// refused naming the query and the element.
TEST_F(Placement, RetreatEndsAtTheQueriedConfigurationAndBadOnesAreRefused) {
  PlacementQuery qr = query(side_grasp());
  Eigen::VectorXd safe(7);
  safe << 0.3, -0.5, 0, -2.0, 0, 1.6, 0.785;
  qr.retreat_configuration = safe;
  const PlacementResult r = solve(qr, 1500, true);
  ASSERT_TRUE(r.solved()) << r.reason;
  const PlacementSolution& s = r.best();
  EXPECT_LT((vec(s.retreat.back()) - safe).norm(), 1e-9);
  Eigen::Isometry3d up = s.pose;
  up.translation().z() += qr.options.lift;
  const ExactChecker released = world_->released_exact(up, s.release_opening);
  for (std::size_t i = 1; i < s.retreat.size(); ++i)
    ASSERT_TRUE(released.segment_free(vec(s.retreat[i - 1]), vec(s.retreat[i]), qr.options.motion_resolution))
        << "retreat " << i;

  qr.source = "q.yaml";
  auto refusal = [&](const Eigen::VectorXd& q) {
    PlacementQuery bad = qr;
    bad.retreat_configuration = q;
    return test::error_of([&] { PlacementPlanner p(*world_, bad); });
  };
  Eigen::VectorXd wide = safe;
  wide[3] = 5;
  EXPECT_NE(refusal(wide).find("q.yaml: retreat_configuration: outside the joint limits"), std::string::npos)
      << refusal(wide);
  Eigen::VectorXd nan = safe;
  nan[0] = std::nan("");
  EXPECT_NE(refusal(nan).find("not finite"), std::string::npos);
  EXPECT_NE(refusal(safe.head(6)).find("has 6 values"), std::string::npos);
  qr.options.retreat_time = 0;
  EXPECT_NE(test::error_of([&] { PlacementPlanner p(*world_, qr); }).find("options.retreat_time"), std::string::npos);
}

TEST_F(Placement, SameSeedOneThreadGivesIdenticalResults) {
  PlacementQuery qr = query(side_grasp());
  qr.seed = 11;
  const PlacementResult a = solve(qr, 400), b = solve(qr, 400);
  ASSERT_EQ(a.improvements.size(), b.improvements.size());
  ASSERT_TRUE(a.solved());
  for (std::size_t k = 0; k < a.improvements.size(); ++k) {
    const auto &x = a.improvements[k], &y = b.improvements[k];
    EXPECT_EQ(x.objective, y.objective);
    EXPECT_EQ(x.grasp_state, y.grasp_state);
    EXPECT_TRUE(x.pose.isApprox(y.pose, 0));
    EXPECT_EQ(x.path, y.path);
    EXPECT_EQ(x.retreat, y.retreat);
  }
  EXPECT_EQ(a.counters.samples, b.counters.samples);
  EXPECT_EQ(a.counters.goals, b.counters.goals);
}

// One world, two synchronous queries at once (the embedding contract): each gets what it gets
// alone, so nothing a query builds or caches is shared with the other.
TEST_F(Placement, TwoQueriesAtOnceOnOneWorldGetWhatEachGetsAlone) {
  const std::uint64_t seeds[2] = {11, 12};
  auto run = [&](std::uint64_t seed) {
    PlacementQuery qr = query(side_grasp());
    qr.seed = seed;
    return solve(qr, 150);
  };
  const ScopedSimdPath restore_simd;  // forced paths end with the test
  for (int round = 0; round < 4; ++round) {
    // Both SIMD paths (a CPU without AVX2 runs the portable one).
    force_simd_path(round % 2 ? SimdPath::Portable : SimdPath::Avx2);
    PlacementResult alone[2], together[2];
    for (int i = 0; i < 2; ++i) alone[i] = run(seeds[i]);
    std::thread other([&] { together[1] = run(seeds[1]); });
    together[0] = run(seeds[0]);
    other.join();
    for (int i = 0; i < 2; ++i) {
      ASSERT_EQ(alone[i].improvements.size(), together[i].improvements.size()) << "seed " << seeds[i];
      for (std::size_t k = 0; k < alone[i].improvements.size(); ++k) {
        EXPECT_EQ(alone[i].improvements[k].objective, together[i].improvements[k].objective);
        EXPECT_EQ(alone[i].improvements[k].path, together[i].improvements[k].path);
      }
      EXPECT_EQ(alone[i].counters.samples, together[i].counters.samples);
      EXPECT_EQ(alone[i].counters.goals, together[i].counters.goals);
    }
  }
}

TEST_F(Placement, ImpossibleQueriesEndWithAReason) {
  PlacementQuery qr = query(side_grasp());
  qr.volume = Eigen::AlignedBox3d(Eigen::Vector3d(3, 3, 0), Eigen::Vector3d(4, 4, 1));  // no region there
  PlacementResult r = solve(qr, 10);
  EXPECT_FALSE(r.solved());
  EXPECT_NE(r.reason.find("no placement region inside the target volume"), std::string::npos) << r.reason;

  qr.volume.reset();
  r = solve(qr, 0);  // zero budget
  EXPECT_FALSE(r.solved());
  EXPECT_NE(r.reason.find("no placement found"), std::string::npos) << r.reason;

  qr.q0[2] = std::nan("");
  EXPECT_NE(test::error_of([&] { PlacementPlanner p(*world_, qr); }).find("q0"), std::string::npos);
  qr.q0[2] = 10;  // beyond the limit
  EXPECT_NE(test::error_of([&] { PlacementPlanner p(*world_, qr); }).find("joint limits"), std::string::npos);
}

TEST_F(Placement, ThreadedPlannerFindsSolutionsToo) {
  PlacementQuery qr = query(side_grasp());
  qr.options.threads = 2;
  PlacementPlanner planner(*world_, qr);
  bool found = false;
  auto deadline = stop_after_seconds(20);
  const PlacementResult r =
      planner.run([&] { return found || deadline(); }, [&](const PlacementSolution&) { found = true; });
  ASSERT_TRUE(r.solved()) << r.reason;
  const ExactChecker exact = world_->grasp_exact(r.best().grasp, r.best().opening);
  for (std::size_t i = 1; i < r.best().path.size(); ++i)
    EXPECT_TRUE(exact.segment_free(vec(r.best().path[i - 1]), vec(r.best().path[i]), qr.options.motion_resolution));
}

// `dmgplace place --time-limit 0`: no time to search is not a failure of the command; it ends
// cleanly (exit 3, the "no solution" code) with the reason on stdout and in result.json.
TEST_F(Placement, PlaceWithNoTimeEndsWithNoSolutionAndAReason) {
  const fs::path d = dir_->path();
  test::write_text(d / "zero.yaml",
                   "robot: arm.h5\nobject: bottle.h5\nenvironment: cabinet.h5\n"
                   "start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n"
                   "initial_grasp: {pose: [0, 0, 0.06, 0, 0.7071068, 0, 0.7071068]}\n");
  const test::ProcessResult place = test::run_cli({"place", d / "zero.yaml", "--time-limit", "0", "--out", d / "zero"});
  const std::string& out = place.output;  // stdout and stderr together
  ASSERT_EQ(place.signal, 0) << out;
  EXPECT_EQ(place.exit_code, 3) << out;
  EXPECT_NE(out.find("no solution: no placement found in"), std::string::npos) << out;
  EXPECT_EQ(out.find("error"), std::string::npos) << out;
  const std::string result = test::read_text(d / "zero/result.json");
  EXPECT_NE(result.find("\"solved\": false"), std::string::npos) << result;
  EXPECT_NE(result.find("\"reason\": \"no placement found in"), std::string::npos) << result;
}

TEST_F(Placement, UnreachableRegionsEndWithAReason) {
  // The same scene with its placement regions moved 0.6 m further from the robot: inside the
  // arm's reach bound (so the set loads), but the arm is too short for every pose: stable and
  // free poses exist, none is reachable.
  auto env = formats::load_environment(dir_->path() / "cabinet.h5");
  for (auto& r : env.regions) r.origin.x() += 0.6;
  env.volume.translate(Eigen::Vector3d(0.6, 0, 0));
  const PlacementWorld far(formats::load_robot(dir_->path() / "arm.h5"),
                           formats::load_object(dir_->path() / "bottle.h5"), std::move(env));
  PlacementPlanner planner(far, query(side_grasp()));
  const PlacementResult r = planner.run(stop_after_iterations(300));
  EXPECT_FALSE(r.solved());
  EXPECT_GT(r.counters.ik_calls, 0);
  EXPECT_EQ(r.counters.ik_solutions, 0);
  EXPECT_NE(r.reason.find("(0 solved,"), std::string::npos) << r.reason;
}

TEST_F(Placement, ASceneBeyondTheArmsReachIsRefusedAtLoad) {
  // 5 m away: no region is within the arm's reach bound, which the loader tells at once instead
  // of searching until the time limit.
  auto env = formats::load_environment(dir_->path() / "cabinet.h5");
  for (auto& r : env.regions) r.origin.x() += 5;
  env.volume.translate(Eigen::Vector3d(5, 0, 0));
  const std::string error = test::error_of([&] {
    PlacementWorld far(formats::load_robot(dir_->path() / "arm.h5"), formats::load_object(dir_->path() / "bottle.h5"),
                       std::move(env));
  });
  EXPECT_NE(error.find("arm.h5"), std::string::npos) << error;
  EXPECT_NE(error.find("cabinet.h5"), std::string::npos) << error;
  EXPECT_NE(error.find("reach"), std::string::npos) << error;
}

TEST_F(Placement, ExactLayerCatchesAWrongSphereModel) {
  // Spheres shrunk to nothing: the fast layer calls almost everything free. Published paths must
  // still be free for the exact layer, because every path is re-validated by it before use.
  auto robot = formats::load_robot(dir_->path() / "arm.h5");
  for (auto& s : robot.spheres) s.radius *= 0.01;
  const PlacementWorld wrong(std::move(robot), formats::load_object(dir_->path() / "bottle.h5"),
                             formats::load_environment(dir_->path() / "cabinet.h5"));
  PlacementQuery qr = query(side_grasp());
  qr.options.check_retreat = false;
  PlacementPlanner planner(wrong, qr);
  const PlacementResult r = planner.run(stop_after_iterations(1500));
  ASSERT_TRUE(r.solved()) << r.reason;
  for (const auto& s : r.improvements) {
    const ExactChecker exact = wrong.grasp_exact(s.grasp, s.opening);
    for (std::size_t i = 1; i < s.path.size(); ++i)
      ASSERT_TRUE(exact.segment_free(vec(s.path[i - 1]), vec(s.path[i]), qr.options.motion_resolution))
          << "segment " << i;
  }
  // Near the placement (inside the distance field) the wrong fast layer calls colliding
  // configurations free: without the exact re-check those would have been published.
  const auto& best = r.best();
  const TwoLayerChecker layers = wrong.grasp_checker(best.grasp, best.opening, nullptr);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0, 0.15);
  int fooled = 0;
  for (int k = 0; k < 3000; ++k) {
    Eigen::VectorXd q = vec(best.path.back());
    for (int i = 0; i < q.size(); ++i) q[i] += noise(rng);
    q = q.cwiseMax(wrong.kinematics().lower()).cwiseMin(wrong.kinematics().upper());
    fooled += layers.fast().is_free(q) && !layers.exact().is_free(q);
  }
  EXPECT_GT(fooled, 0);
}
