// make_arm_space's joint space: its default projection (the first two joints, set up without
// sampling) and an OMPL planner that needs a projection planning on it.
#include <gtest/gtest.h>

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/kpiece/KPIECE1.h>

#include <random>

#include "planar_3r.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"

namespace ob = ompl::base;
namespace og = ompl::geometric;
using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {
// The planar 3R arm's configurations are "valid" outside a slab of the first joint's range that
// the second joint must be folded to cross (a joint-space wall with one gap).
bool outside_wall(const Eigen::VectorXd& q) { return std::abs(q[0]) > 0.2 || q[1] > 1.5; }
}  // namespace

TEST(ArmSpace, DefaultProjectionIsTheFirstTwoJointsAndProjectionPlannersSolve) {
  const Kinematics kin(test::planar_3r(), "base", "l3");
  auto si = make_arm_space(kin, outside_wall, 0.01);
  const auto proj = si->getStateSpace()->getDefaultProjection();
  ASSERT_TRUE(proj);
  ASSERT_EQ(proj->getDimension(), 2u);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  ob::ScopedState<> s(si->getStateSpace());
  Eigen::VectorXd p(2);
  for (int i = 0; i < 100; ++i) {
    for (unsigned k = 0; k < 3; ++k) s[k] = u(rng);
    proj->project(s.get(), p);
    EXPECT_EQ(p[0], s[0]);
    EXPECT_EQ(p[1], s[1]);
  }
  // KPIECE1 grids the projection: it must find a way through the wall's gap.
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start(si->getStateSpace()), goal(si->getStateSpace());
  start[0] = -1.5, start[1] = 0, start[2] = 0;
  goal[0] = 1.5, goal[1] = 0, goal[2] = 0;
  pdef->setStartAndGoalStates(start, goal, 1e-6);
  og::KPIECE1 planner(si);
  planner.setProblemDefinition(pdef);
  planner.setup();
  ASSERT_TRUE(bool(planner.solve(ob::timedPlannerTerminationCondition(10.0))));
  ASSERT_TRUE(pdef->hasExactSolution());
  auto path = *pdef->getSolutionPath()->as<og::PathGeometric>();
  EXPECT_TRUE(path.check());
  // Densely interpolated, every state is valid and some lie in the gap (the first joint goes from
  // -1.5 to 1.5, so the path must pass through it).
  path.interpolate(400);
  bool crossed_in_gap = false;
  for (std::size_t i = 0; i < path.getStateCount(); ++i) {
    const auto* v = path.getState(i)->as<ob::RealVectorStateSpace::StateType>();
    const Eigen::Vector3d q(v->values[0], v->values[1], v->values[2]);
    ASSERT_TRUE(outside_wall(q)) << q.transpose();
    crossed_in_gap |= std::abs(q[0]) <= 0.2;
  }
  EXPECT_TRUE(crossed_in_gap);
}
