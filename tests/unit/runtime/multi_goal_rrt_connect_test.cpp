#include <gtest/gtest.h>

#include <ompl/base/DiscreteMotionValidator.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <atomic>
#include <chrono>
#include <set>
#include <thread>

#include "dmgplace/runtime/motion/multi_goal_rrt_connect.hpp"
#include "dmgplace/runtime/motion/multi_grasp_planner.hpp"

namespace ob = ompl::base;
using dmgplace::runtime::FoundPath;
using dmgplace::runtime::MultiGoalRRTConnect;

namespace {
struct Box {
  double x0, y0, x1, y1;
};
// A wall with a gap at the top, and a closed enclosure around (8, 2).
const std::vector<Box> kBoxes = {
    {4.8, 0, 5.2, 8},                                                  // wall, gap y in (8, 10)
    {7, 1, 9, 1.2},   {7, 2.8, 9, 3}, {7, 1, 7.2, 3}, {8.8, 1, 9, 3},  // enclosure
};

bool free_point(double x, double y, double margin = 0, const std::vector<Box>& boxes = kBoxes) {
  for (const auto& b : boxes)
    if (x >= b.x0 - margin && x <= b.x1 + margin && y >= b.y0 - margin && y <= b.y1 + margin) return false;
  return true;
}
// The planners check states every 0.002 of the extent (0.028) against boxes grown by half that:
// every point of a segment is then within half a step of a checked state, so a path valid for the
// planner is free of the true boxes everywhere, which expect_valid_path checks 2000 times finer.
// (Against the true boxes alone, a segment could cut a corner between two checked states.)
constexpr double kMargin = 0.015;

struct Problem {
  ob::SpaceInformationPtr si;
  ob::ProblemDefinitionPtr pdef;
  std::shared_ptr<MultiGoalRRTConnect> planner;
};

Problem make(std::uint64_t seed, const std::vector<Box>& boxes = kBoxes) {
  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  space->setBounds(0, 10);
  Problem p;
  p.si = std::make_shared<ob::SpaceInformation>(space);
  p.si->setStateValidityChecker([boxes](const ob::State* s) {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    return free_point(v->values[0], v->values[1], kMargin, boxes);
  });
  p.si->setStateValidityCheckingResolution(0.002);  // 0.002 * extent ~ 0.028
  p.si->setup();
  p.pdef = std::make_shared<ob::ProblemDefinition>(p.si);
  ob::ScopedState<> start(space);
  start[0] = 1;
  start[1] = 1;
  p.pdef->addStartState(start);
  p.planner = std::make_shared<MultiGoalRRTConnect>(p.si);
  p.planner->setProblemDefinition(p.pdef);
  p.planner->set_seed(seed);
  p.planner->setup();
  return p;
}

// Every segment free when checked far finer than the planner's resolution.
void expect_valid_path(const FoundPath& f, double gx, double gy, const std::vector<Box>& boxes = kBoxes) {
  ASSERT_GE(f.path.size(), 2u);
  EXPECT_DOUBLE_EQ(f.path.front()[0], 1);
  EXPECT_DOUBLE_EQ(f.path.front()[1], 1);
  EXPECT_NEAR(f.path.back()[0], gx, 1e-12);
  EXPECT_NEAR(f.path.back()[1], gy, 1e-12);
  for (std::size_t i = 1; i < f.path.size(); ++i) {
    const auto &a = f.path[i - 1], &b = f.path[i];
    const int n = 2000;
    for (int k = 0; k <= n; ++k) {
      const double t = double(k) / n;
      ASSERT_TRUE(free_point(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0, boxes)) << "segment " << i;
    }
  }
}
}  // namespace

TEST(MultiGoalRRTConnect, FindsReachableGoalsNeverWalledOffOrRemovedOnes) {
  Problem p = make(7);
  ASSERT_TRUE(p.planner->add_goal(1, {8, 8}));  // behind the wall, through the gap
  ASSERT_TRUE(p.planner->add_goal(2, {8, 2}));  // walled off: never reachable
  ASSERT_TRUE(p.planner->add_goal(3, {2, 8}));  // same side as the start
  ASSERT_TRUE(p.planner->add_goal(4, {9.5, 9.5}));
  p.planner->remove_goal(4);                     // removed before it could connect
  EXPECT_FALSE(p.planner->add_goal(5, {5, 4}));  // inside the wall: refused
  std::vector<FoundPath> found;
  std::thread solver([&] { p.planner->solve(ob::timedPlannerTerminationCondition(1.5)); });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(p.planner->add_goal(6, {9.5, 5}));  // added while solving
  solver.join();
  found = p.planner->take_paths();
  std::map<int, FoundPath> by_id;
  for (auto& f : found) by_id[f.goal_id] = f;
  EXPECT_EQ(by_id.count(1), 1u);
  EXPECT_EQ(by_id.count(3), 1u);
  EXPECT_EQ(by_id.count(6), 1u) << "a goal added mid-run gets connected";
  EXPECT_EQ(by_id.count(2), 0u) << "walled-off goal reported";
  EXPECT_EQ(by_id.count(4), 0u) << "removed goal reported";
  EXPECT_EQ(found.size(), by_id.size()) << "each goal is reported once";
  if (by_id.count(1)) expect_valid_path(by_id[1], 8, 8);
  if (by_id.count(3)) expect_valid_path(by_id[3], 2, 8);
  if (by_id.count(6)) expect_valid_path(by_id[6], 9.5, 5);
  // The walled-off goal is still being searched for; nothing else remains.
  EXPECT_EQ(p.planner->goal_count(), 1u);
}

TEST(MultiGoalRRTConnect, SingleThreadRunsAreDeterministicUnderASeed) {
  auto run = [](std::uint64_t seed) {
    Problem p = make(seed);
    p.planner->set_anytime(false);
    p.planner->add_goal(1, {8, 8});
    p.planner->solve(ob::timedPlannerTerminationCondition(5.0));
    auto f = p.planner->take_paths();
    return f.empty() ? dmgplace::runtime::JointPath{} : f[0].path;
  };
  auto a = run(3), b = run(3), c = run(4);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

// The straight start-goal line is tried once, when the goal arrives: the wall blocks it, so
// shortcutting the found path does not try it again.
TEST(MultiGoalRRTConnect, BlockedStartGoalLineIsTriedOnce) {
  Problem p = make(3);
  struct Counting : ob::DiscreteMotionValidator {
    using ob::DiscreteMotionValidator::DiscreteMotionValidator;
    bool checkMotion(const ob::State* a, const ob::State* b) const override {
      const auto *u = a->as<ob::RealVectorStateSpace::StateType>(), *v = b->as<ob::RealVectorStateSpace::StateType>();
      direct += u->values[0] == 1 && u->values[1] == 1 && v->values[0] == 8 && v->values[1] == 8;
      ++all;
      return ob::DiscreteMotionValidator::checkMotion(a, b);
    }
    mutable int direct = 0, all = 0;
  };
  auto counting = std::make_shared<Counting>(p.si);
  p.si->setMotionValidator(counting);
  p.planner->set_anytime(false);
  p.planner->add_goal(1, {8, 8});
  p.planner->solve(ob::timedPlannerTerminationCondition(5.0));
  auto f = p.planner->take_paths();
  ASSERT_EQ(f.size(), 1u);
  expect_valid_path(f[0], 8, 8);
  EXPECT_GE(f[0].path.size(), 3u) << "the wall is in the way";
  EXPECT_GT(counting->all, 10);
  EXPECT_EQ(counting->direct, 1);
}

// Balanced growth: the smaller tree grows toward each sample, so a goal in a pocket (a slot 0.4
// wide in its left wall, behind the wall's gap) gets as many tree nodes as the open start side.
// The trees then differ by at most what one connect adds to the larger tree (one range per node,
// 5% of the extent once the wide phase ends, so about 20 across this world) at every meeting.
// Alternating which tree grows leaves the pocket's tree a few nodes against hundreds.
TEST(MultiGoalRRTConnect, TheSmallerTreeGrowsSoAPocketedGoalsTreeKeepsUp) {
  std::vector<Box> boxes = kBoxes;
  for (const Box& b : std::vector<Box>{{7.4, 6, 10, 6.2}, {7.4, 3.8, 10, 4}, {7.4, 4, 7.6, 4.8}, {7.4, 5.2, 7.6, 6}})
    boxes.push_back(b);
  std::size_t nodes = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    Problem p = make(seed, boxes);
    p.planner->set_anytime(false);
    ASSERT_TRUE(p.planner->add_goal(1, {9, 5}));
    p.planner->solve(ob::timedPlannerTerminationCondition(5.0));
    const auto f = p.planner->take_paths();
    ASSERT_EQ(f.size(), 1u) << "seed " << seed;
    expect_valid_path(f[0], 9, 5, boxes);
    EXPECT_LE(f[0].start_nodes, f[0].goal_nodes + 25) << "seed " << seed;
    EXPECT_LE(f[0].goal_nodes, f[0].start_nodes + 25) << "seed " << seed;
    nodes += f[0].start_nodes + f[0].goal_nodes;
  }
  EXPECT_GE(nodes, 8 * 40u) << "the pocket should take a search, not a lucky early connection";
}

TEST(MultiGoalRRTConnect, ValidatorCanRejectAPathAndSingleQueryModeFillsTheProblemDefinition) {
  Problem p = make(5);
  p.planner->set_anytime(false);
  int calls = 0;
  p.planner->set_path_validator([&](const dmgplace::runtime::JointPath&) { return ++calls > 1; });
  p.planner->add_goal(1, {2, 8});
  p.planner->add_goal(2, {3, 9});
  auto status = p.planner->solve(ob::timedPlannerTerminationCondition(5.0));
  EXPECT_EQ(status, ob::PlannerStatus::EXACT_SOLUTION);
  EXPECT_EQ(calls, 2) << "the first path was rejected, the second accepted";
  EXPECT_TRUE(p.pdef->hasSolution());
  const auto paths = p.planner->take_paths();
  ASSERT_EQ(paths.size(), 1u);
  // The refused goal is reported once, so a caller can stop counting it as open.
  const std::vector<int> rejected = p.planner->take_rejected();
  ASSERT_EQ(rejected.size(), 1u);
  EXPECT_NE(rejected[0], paths[0].goal_id);
  EXPECT_TRUE(rejected[0] == 1 || rejected[0] == 2);
  EXPECT_TRUE(p.planner->take_rejected().empty());
}

// A start tree grown in a space whose wall has its gap at the bottom, handed to a planner whose
// wall has it at the top: the recipient's paths are free of its wall everywhere (the seeded edges on the way are checked in its
// own space), nodes whose edges cross the wall leave with their subtrees, the seeded nodes that
// held carry connections, and a snapshot of what is left is a tree again (parents first, no
// dropped node). A seed from another start is ignored.
TEST(MultiGoalRRTConnect, ASeededStartTreeIsCheckedInTheRecipientsSpaceBeforeItCarriesAPath) {
  const auto until_connected = [](const MultiGoalRRTConnect& planner, double seconds) {
    return ob::plannerOrTerminationCondition(
        ob::timedPlannerTerminationCondition(seconds),
        ob::PlannerTerminationCondition([&] { return planner.goal_count() == 0; }));
  };
  std::size_t checked = 0, dropped = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    Problem donor = make(seed, {{4.8, 2, 5.2, 10}});
    for (int g = 0; g < 6; ++g) ASSERT_TRUE(donor.planner->add_goal(g, {6 + 0.7 * g, g % 2 ? 8.5 : 4.5}));
    donor.planner->solve(until_connected(*donor.planner, 2.0));
    const auto seed_nodes = donor.planner->start_tree_snapshot();
    ASSERT_GT(seed_nodes.size(), 10u);
    Problem p = make(seed);
    p.planner->seed_start_tree(seed_nodes);
    ASSERT_TRUE(p.planner->add_goal(1, {8, 8}));
    ASSERT_TRUE(p.planner->add_goal(2, {9.5, 5}));
    ASSERT_TRUE(p.planner->add_goal(3, {2, 8}));
    p.planner->solve(until_connected(*p.planner, 3.0));
    EXPECT_GE(p.planner->start_tree_size(), seed_nodes.size());
    const auto found = p.planner->take_paths();
    EXPECT_EQ(found.size(), 3u) << "seed " << seed;
    for (const auto& f : found) expect_valid_path(f, f.path.back()[0], f.path.back()[1]);
    checked += p.planner->seeded_nodes_checked();
    dropped += p.planner->seeded_nodes_dropped();
    const auto left = p.planner->start_tree_snapshot();
    EXPECT_EQ(left.size() + p.planner->seeded_nodes_dropped(), p.planner->start_tree_size());
    ASSERT_FALSE(left.empty());
    EXPECT_EQ(left[0].q, (std::vector<double>{1, 1}));
    for (std::size_t i = 1; i < left.size(); ++i) EXPECT_LT(left[i].parent, i);

    Problem elsewhere = make(seed);
    auto moved = seed_nodes;
    moved[0].q = {1.5, 1};
    elsewhere.planner->seed_start_tree(moved);
    elsewhere.planner->solve(ob::timedPlannerTerminationCondition(0.01));
    EXPECT_EQ(elsewhere.planner->start_tree_size(), 1u) << "a tree from another start";
  }
  EXPECT_GT(checked, 0u);
  EXPECT_GT(dropped, 0u) << "the donor's tree crosses the wall somewhere on the recipient's way";
}

// Two grasps, two collision spaces: in grasp 1 the gap in the wall is closed, so its goal behind
// the wall is unreachable; grasp 0's is reachable. Two workers serve both.
TEST(MultiGraspPlanner, ServesEachGraspInItsOwnSpace) {
  auto factory = [](int grasp) {
    auto space = std::make_shared<ob::RealVectorStateSpace>(2);
    space->setBounds(0, 10);
    auto si = std::make_shared<ob::SpaceInformation>(space);
    si->setStateValidityChecker([grasp](const ob::State* s) {
      const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
      const double x = v->values[0], y = v->values[1];
      if (grasp == 1 && x >= 4.8 && x <= 5.2) return false;  // wall without a gap
      return free_point(x, y, kMargin);
    });
    si->setStateValidityCheckingResolution(0.002);
    si->setup();
    return ob::SpaceInformationPtr(si);
  };
  dmgplace::runtime::MultiGraspPlanner mgp(factory, {1, 1}, 2, 11);
  std::atomic<int> validated{0};
  mgp.set_path_validator([&](int, const dmgplace::runtime::JointPath&) {
    ++validated;
    return true;
  });
  ASSERT_TRUE(mgp.add_goal(0, 10, {8, 8}));
  ASSERT_TRUE(mgp.add_goal(1, 11, {8, 8}));
  ASSERT_TRUE(mgp.add_goal(1, 12, {2, 8}));
  mgp.start();
  std::vector<dmgplace::runtime::GraspPath> all;
  for (int i = 0; i < 150 && all.size() < 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    for (auto& p : mgp.take_paths()) all.push_back(p);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  mgp.stop();
  for (auto& p : mgp.take_paths()) all.push_back(p);
  std::set<std::pair<int, int>> got;
  for (auto& p : all) {
    got.insert({p.grasp, p.found.goal_id});
    expect_valid_path(p.found, p.found.path.back()[0], p.found.path.back()[1]);
  }
  EXPECT_TRUE(got.count({0, 10}));
  EXPECT_TRUE(got.count({1, 12}));
  EXPECT_FALSE(got.count({1, 11})) << "unreachable in grasp 1's space";
  EXPECT_EQ(validated.load(), int(all.size()));
}

TEST(MultiGraspPlanner, APathFoundInsideAWorkersSliceIsTakenWithoutWaitingForItsEnd) {
  auto factory = [](int) {
    auto space = std::make_shared<ob::RealVectorStateSpace>(2);
    space->setBounds(0, 10);
    auto si = std::make_shared<ob::SpaceInformation>(space);
    si->setStateValidityChecker([](const ob::State* s) {
      const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
      return free_point(v->values[0], v->values[1], kMargin);
    });
    si->setStateValidityCheckingResolution(0.002);
    si->setup();
    return ob::SpaceInformationPtr(si);
  };
  // A slice that does not end before stop(): the path must still come out while the worker runs.
  dmgplace::runtime::MultiGraspPlanner mgp(factory, {1, 1}, 1, 5, 1e9);
  ASSERT_TRUE(mgp.add_goal(0, 7, {2, 2}));
  mgp.start();
  std::vector<dmgplace::runtime::GraspPath> taken;
  for (int i = 0; i < 3000 && taken.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    taken = mgp.take_paths();
  }
  mgp.stop();
  ASSERT_EQ(taken.size(), 1u) << "taken while the worker was inside its slice";
  EXPECT_EQ(taken[0].grasp, 0);
  EXPECT_EQ(taken[0].found.goal_id, 7);
  expect_valid_path(taken[0].found, 2, 2);
}
