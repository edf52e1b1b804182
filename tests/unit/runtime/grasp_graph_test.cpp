// Grasp graph and reachable grasps: Dijkstra against Bellman-Ford, a full in-hand turn on a cube,
// snapping, and the action sequences.
#include "dmgplace/runtime/grasp/reachable_grasps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <tuple>

#include "fixtures.hpp"

namespace dmgplace::runtime {
namespace {

std::vector<double> bellman_ford(int n, const std::vector<std::tuple<int, int, double>>& edges, int source) {
  std::vector<double> d(n, std::numeric_limits<double>::infinity());
  d[source] = 0;
  for (int round = 0; round < n; ++round)
    for (auto [a, b, c] : edges)
      if (d[a] + c < d[b]) d[b] = d[a] + c;
  return d;
}

TEST(ShortestPaths, DijkstraMatchesBellmanFordOnRandomGraphs) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + int(rng() % 30);
    const int m = int(rng() % (4 * n + 1));
    std::vector<std::tuple<int, int, double>> edges;
    for (int e = 0; e < m; ++e)
      edges.emplace_back(int(rng() % n), int(rng() % n),
                         (rng() % 4 == 0) ? 0.0 : std::uniform_real_distribution<double>(0, 5)(rng));
    const int source = int(rng() % n);
    const auto g = WeightedGraph::from_edges(n, edges);
    const auto r = dijkstra(g, source);
    const auto ref = bellman_ford(n, edges, source);
    for (int v = 0; v < n; ++v) {
      if (std::isinf(ref[v])) {
        EXPECT_TRUE(std::isinf(r.cost[v]));
        continue;
      }
      EXPECT_NEAR(r.cost[v], ref[v], 1e-9) << "trial " << trial << " vertex " << v;
      // The predecessor chain is a real path with exactly that cost.
      double along = 0;
      for (int w = v; w != source; w = r.predecessor[w]) {
        ASSERT_GE(r.predecessor[w], 0);
        EXPECT_EQ(g.targets[r.via_edge[w]], w);
        along += g.costs[r.via_edge[w]];
      }
      EXPECT_NEAR(along, r.cost[v], 1e-9);
    }
  }
  EXPECT_THROW(dijkstra(WeightedGraph::from_edges(2, {}), 2), std::out_of_range);
}

// 60 mm across x; 35 mm square in y-z, small enough for the palm to pass over at every angle.
GraspGraph cube_graph() {
  const auto dmg = test::dmg(test::box_mesh({0.06, 0.035, 0.035}));
  return GraspGraph(dmg, formats::build_grasp_graph_table(dmg));
}

// The TCP pose of a grasp across the box's x sides at the face centers, approach angle a about x.
Eigen::Isometry3d across_x(double a) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d r;
  r.col(1) = Eigen::Vector3d::UnitX();
  r.col(2) = Eigen::Vector3d(0, std::cos(a), std::sin(a));
  r.col(0) = r.col(1).cross(r.col(2));
  t.linear() = r;
  return t;
}

TEST(ReachableGrasps, AGraspAcrossABoxTurnsAllTheWayRound) {
  const GraspGraph g = cube_graph();
  const auto r = reachable_grasps(g, across_x(0.3), 0.06);
  ASSERT_GE(r.initial_state, 0);
  const int node = g.state(r.initial_state).node;
  EXPECT_LT(g.tcp_pose(r.initial_state).translation().norm(), 0.006);
  const int k = g.dmg().angle_count();
  // Every angle of the same contact pair is reachable, by rotation alone, at the shorter way round.
  for (int a = 0; a < k; ++a) {
    const int s = g.find(node, a);
    ASSERT_GE(s, 0) << "angle " << a;
    const int turns =
        std::min((a - g.state(r.initial_state).angle + k) % k, (g.state(r.initial_state).angle - a + k) % k);
    EXPECT_NEAR(r.paths.cost[s], turns * g.angle_step() * 0.1, 1e-9);
    const auto acts = r.actions_to(g, s);
    if (turns == 0) continue;
    ASSERT_EQ(acts.size(), 1u);
    EXPECT_EQ(acts[0].type, GraspMove::Rotation);
    EXPECT_NEAR(std::abs(acts[0].angle), turns * g.angle_step(), 1e-9);
    // Applying the rotation to the initial pose gives the target pose.
    const Eigen::Matrix3d rot = Eigen::AngleAxisd(acts[0].angle, acts[0].axis).toRotationMatrix();
    EXPECT_LT((rot * g.tcp_pose(r.initial_state).linear() - g.tcp_pose(s).linear()).norm(), 1e-9);
  }
}

TEST(ReachableGrasps, TranslationsCarryContactPathsAndCosts) {
  const GraspGraph g = cube_graph();
  const auto r = reachable_grasps(g, across_x(0), 0.06);
  ASSERT_GE(r.initial_state, 0);
  // The grasps on the same pair of sides are reachable by sliding; their costs are path lengths.
  int checked = 0;
  for (const auto& gr : r.grasps) {
    const auto acts = r.actions_to(g, gr.state);
    double cost = 0;
    for (const auto& a : acts) {
      if (a.type == GraspMove::Translation) {
        ASSERT_GE(a.finger1_path.size(), 2u);
        EXPECT_NEAR(a.push_direction.norm(), 1.0, 1e-9);
        double len = 0;
        for (std::size_t i = 1; i < a.finger1_path.size(); ++i)
          len += (a.finger1_path[i] - a.finger1_path[i - 1]).norm();
        EXPECT_NEAR(len, a.distance, 1e-12);
        EXPECT_EQ(a.finger1_path.back(), g.contact1(a.to_state));
        EXPECT_EQ(a.finger2_path.back(), g.contact2(a.to_state));
        cost += a.distance;
        ++checked;
      } else {
        cost += std::abs(a.angle) * 0.1;
      }
    }
    EXPECT_NEAR(cost, gr.cost, 1e-9);
    EXPECT_NEAR(gr.opening, 0.06, 1e-6);
  }
  EXPECT_GT(checked, 0);
  for (std::size_t i = 1; i < r.grasps.size(); ++i) EXPECT_LE(r.grasps[i - 1].cost, r.grasps[i].cost);
  EXPECT_EQ(r.grasps.front().state, r.initial_state);
}

TEST(ReachableGrasps, SnapFindsTheExactStateAndItsFlip) {
  const GraspGraph g = cube_graph();
  ASSERT_GT(g.size(), 0);
  const Eigen::Matrix3d flip = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  // The same gripper turned 180 degrees about its approach axis is the same grasp (the state with
  // the fingers' roles swapped may be found instead: same TCP, flipped frame).
  auto same_grasp = [&](int a, const Eigen::Isometry3d& p) {
    const Eigen::Isometry3d q = g.tcp_pose(a);
    return (q.translation() - p.translation()).norm() < 1e-9 &&
           ((q.linear() - p.linear()).norm() < 1e-9 || (q.linear() * flip - p.linear()).norm() < 1e-9);
  };
  for (int s = 0; s < g.size(); s += 97) {
    double d = 1;
    EXPECT_TRUE(same_grasp(g.snap(g.tcp_pose(s), g.opening(s), &d), g.tcp_pose(s)));
    EXPECT_LT(d, 1e-9);
    Eigen::Isometry3d flipped = g.tcp_pose(s);
    flipped.linear() = flipped.linear() * flip;
    EXPECT_TRUE(same_grasp(g.snap(flipped, std::nullopt, &d), g.tcp_pose(s)));
    EXPECT_LT(d, 1e-9);
    // A pose 2 cm away snaps to a grasp at most about that far away.
    Eigen::Isometry3d off = g.tcp_pose(s);
    off.translation() += Eigen::Vector3d(0, 0.02, 0);
    EXPECT_LE(g.snap(off, std::nullopt, &d), g.size());
    EXPECT_LE(d, 0.02 + 1e-9);
  }
  const GraspGraph empty(formats::Dmg{}, formats::GraspGraphTable{});
  EXPECT_EQ(reachable_grasps(empty, Eigen::Isometry3d::Identity()).initial_state, -1);
}

}  // namespace
}  // namespace dmgplace::runtime
