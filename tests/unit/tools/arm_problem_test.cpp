// Planning real MotionBenchMaker problems with the Panda: ours and bench-mbm's stock OMPL+FCL
// baseline both return paths that the exact checker accepts at the stated resolution.
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/motion/arm_problem.hpp"
#include "dmgplace/tools/robot/bake_robot.hpp"
#include "stock_planner.hpp"
#include "test_support.hpp"

using namespace dmgplace;

TEST(ArmProblem, PandaMbmProblemsSolveWithPathsValidAtTheResolution) {
  DMGPLACE_REQUIRE_SHARED();
  auto shared = test::shared_datasets();
  test::TempDir dir;
  tools::RobotBakeOptions o;
  o.urdf = shared / "panda/moveit_resources_panda_description/urdf/panda.urdf";
  o.srdf = shared / "panda/panda_moveit_config/config/panda.srdf";
  o.package_paths = {shared / "panda"};
  o.arm_base = "panda_link0";
  o.arm_tip = "panda_hand";
  formats::save_robot(tools::bake_robot(o), dir / "panda.h5");
  for (auto set : {"bookshelf_small_panda", "table_pick_panda"}) {
    auto folder = shared / "mbm_problems" / set;
    auto p = tools::load_arm_problem(dir / "panda.h5", folder / "scene0001.yaml", folder / "request0001.yaml");
    ASSERT_TRUE(p.exact->is_free(p.start)) << set << ": the start must be free (fingers at the request's 0.065)";
    ASSERT_TRUE(p.exact->is_free(p.goal)) << set;
    auto ours = tools::plan_ours(p, 20.0, 0.01, 1);
    ASSERT_TRUE(ours.solved) << set;
    EXPECT_TRUE(ours.valid) << set;
    EXPECT_LT((Eigen::Map<const Eigen::VectorXd>(ours.path.front().data(), 7) - p.start).norm(), 1e-12);
    EXPECT_LT((Eigen::Map<const Eigen::VectorXd>(ours.path.back().data(), 7) - p.goal).norm(), 1e-12);
    // The time to the first path (before shortcutting) is recorded; bench-mbm compares it.
    EXPECT_GT(ours.first_path_seconds, 0.0) << set;
    const bench::StockFclChecker stock_checker(*p.kin, p.scene);
    auto stock = bench::plan_stock(p, stock_checker, 20.0, 0.01);
    EXPECT_TRUE(stock.solved && stock.valid) << set;
    EXPECT_EQ(stock.first_path_seconds, stock.seconds) << set << ": the stock planner does not shorten";
    // The baseline's checker (OBBRSS hierarchies, MoveIt's) and our exact layer answer alike.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    int collide = 0;
    for (int i = 0; i < 2000; ++i) {
      Eigen::VectorXd q(7);
      for (int j = 0; j < 7; ++j) q[j] = p.kin->lower()[j] + u(rng) * (p.kin->upper()[j] - p.kin->lower()[j]);
      const bool obb = p.exact->is_free(q);
      collide += !obb;
      ASSERT_EQ(obb, stock_checker.is_free(q)) << set << " q = " << q.transpose();
    }
    EXPECT_GT(collide, 200) << set << ": the comparison must include collisions";
  }
}

TEST(ArmProblem, RequestsNamingUnknownJointsOrMissingGoalsAreRejected) {
  test::TempDir dir;
  test::write_text(dir / "bad.yaml", "start_state:\n  joint_state:\n    name: [a]\n    position: [0]\n");
  tools::RobotBakeOptions o;
  o.urdf = test::source_dir() / "datasets/robots/dmgarm/dmgarm.urdf";
  o.arm_base = "dmgarm_link0";
  o.arm_tip = "dmgarm_tcp";
  formats::save_robot(tools::bake_robot(o), dir / "arm.h5");
  test::write_text(dir / "scene.yaml",
                   "world:\n  collision_objects:\n    - id: box\n      primitives:\n        - type: box\n"
                   "          dimensions: [0.1, 0.1, 0.1]\n      primitive_poses:\n        - position: [2, 0, 0]\n"
                   "          orientation: [0, 0, 0, 1]\n");
  try {
    tools::load_arm_problem(dir / "arm.h5", dir / "scene.yaml", dir / "bad.yaml");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
  }
}
