// plan_free_motion with a tree shared by motions from one start: later motions begin from what
// earlier ones grew, and use it only where their own validity holds.
#include <gtest/gtest.h>

#include <cmath>

#include "planar_3r.hpp"
#include "dmgplace/runtime/motion/free_motion.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {

// A joint-space wall across the first joint (|q0| <= 0.2) with its one gap where side * q1 > 1.5.
// The planners check a wall grown by `margin`, so a path they accept at their resolution is clear
// of the true wall everywhere, which expect_clear samples far finer.
constexpr double kMargin = 0.02;
bool clear_of(const Eigen::VectorXd& q, double side, double margin) {
  return std::abs(q[0]) > 0.2 + margin || side * q[1] > 1.5 + margin;
}

void expect_clear(const JointPath& path, double side) {
  for (std::size_t i = 1; i < path.size(); ++i)
    for (int k = 0; k <= 1000; ++k) {
      Eigen::VectorXd q(3);
      for (int d = 0; d < 3; ++d) q[d] = path[i - 1][d] + (path[i][d] - path[i - 1][d]) * k / 1000.0;
      ASSERT_TRUE(clear_of(q, side, 0)) << "segment " << i << " at " << q.transpose();
    }
}
}  // namespace

// The first motion grows a tree through the wall's top gap; the same wall again, to a goal nearby,
// needs far fewer checks on that tree; a wall whose gap is at the bottom gets a path through its
// own gap, the seeded edges through the top one refused (without the re-check, that path would
// cross this wall).
TEST(FreeMotion, ATreeFromEarlierMotionsCarriesLaterOnesOnlyWhereTheirOwnChecksHold) {
  const Kinematics kin(test::planar_3r(), "base", "l3");
  MotionBudget budget;
  budget.resolution = 0.01;
  budget.iterations = 50000;
  budget.seconds = 20;
  Eigen::VectorXd start(3), goal(3), near_goal(3);
  start << -1.5, 0, 0;
  goal << 1.5, 0, 0;
  near_goal << 1.4, 0.2, 0.1;
  int fewer = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    budget.seed = seed;
    MotionTree tree;
    int first_checks = 0, again_checks = 0;
    const JointPath first = plan_free_motion(
        kin, [&](const Eigen::VectorXd& q) { return ++first_checks, clear_of(q, +1, kMargin); }, start, goal, budget,
        &tree);
    ASSERT_FALSE(first.empty()) << "seed " << seed;
    expect_clear(first, +1);
    ASSERT_GT(tree.nodes.size(), 1u);
    EXPECT_EQ(tree.nodes[0].q, std::vector<double>(start.data(), start.data() + 3));
    for (std::size_t i = 1; i < tree.nodes.size(); ++i) EXPECT_LT(tree.nodes[i].parent, i);

    const JointPath again = plan_free_motion(
        kin, [&](const Eigen::VectorXd& q) { return ++again_checks, clear_of(q, +1, kMargin); }, start, near_goal,
        budget, &tree);
    ASSERT_FALSE(again.empty()) << "seed " << seed;
    expect_clear(again, +1);
    fewer += again_checks < first_checks;

    const JointPath other = plan_free_motion(
        kin, [](const Eigen::VectorXd& q) { return clear_of(q, -1, kMargin); }, start, goal, budget, &tree);
    ASSERT_FALSE(other.empty()) << "seed " << seed;
    expect_clear(other, -1);
  }
  EXPECT_GE(fewer, 4) << "the second motion to a nearby goal should mostly cost less on the tree";
}
