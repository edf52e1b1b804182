// The DMG on analytic shapes: facets, sliding all round a cylinder, contacts on the surface,
// symmetric edges, and the artifact invariants of `dmgplace validate`.
#include "dmgplace/tools/object/dmg_builder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <queue>
#include <set>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/geometry/procedural_meshes.hpp"
#include "dmgplace/tools/object/gripper_model.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"
#include "dmgplace/tools/object/placement_faces.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

formats::ObjectArtifact bake(const TriMesh& mesh, const DmgOptions& o = {}) {
  formats::ObjectArtifact a;
  a.mesh = mesh;
  a.mass = compute_mass_properties(mesh, 0, "test");
  a.placement = compute_placement_faces(mesh, a.mass.com, {}, "test");
  a.dmg = build_dmg(mesh, default_gripper(), o, "test");
  a.grasp_graph = formats::build_grasp_graph_table(a.dmg);
  return a;
}

TEST(Dmg, ABoxsFacetsAreItsSixSides) {
  const auto a = bake(make_box_mesh({0.05, 0.07, 0.09}));
  ASSERT_EQ(a.dmg.facet_normals.size(), 6u);
  std::set<std::pair<int, int>> sides;  // (axis, sign)
  for (const auto& n : a.dmg.facet_normals) {
    int axis = 0;
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(&axis), 1.0, 1e-9);
    sides.insert({axis, n[axis] > 0 ? 1 : -1});
  }
  EXPECT_EQ(sides.size(), 6u);
  // Every node lies on its facet's side, normal equal to the side's.
  for (const auto& node : a.dmg.nodes) EXPECT_NEAR(node.normal.dot(a.dmg.facet_normals[node.facet]), 1.0, 1e-9);
  EXPECT_TRUE(check_object(a).empty()) << check_object(a).front();
}

TEST(Dmg, NodesAreOnTheSurfaceAndGraspWithinTheOpening) {
  const auto a = bake(make_box_mesh({0.05, 0.07, 0.09}));
  ASSERT_FALSE(a.dmg.nodes.empty());
  for (const auto& n : a.dmg.nodes) {
    // On a box the contact is on the face whose normal it carries, the opposite on the parallel face.
    int axis = 0;
    n.normal.cwiseAbs().maxCoeff(&axis);
    const double half[3] = {0.025, 0.035, 0.045};
    EXPECT_NEAR(std::abs(n.position[axis]), half[axis], 1e-9);
    EXPECT_NEAR(n.opposite_point[axis], -n.position[axis], 1e-6);
    EXPECT_LE((n.position - n.opposite_point).norm(), default_gripper().max_opening);
  }
  // The 0.09 side is wider than the 0.08 opening: no node may grasp across it.
  for (const auto& n : a.dmg.nodes) EXPECT_LT(std::abs(n.normal.z()), 0.5);
}

TEST(Dmg, EdgesAreSymmetricAndJoinAdjacentPatchesOfOneFacet) {
  const auto a = bake(make_box_mesh({0.05, 0.07, 0.09}));
  ASSERT_FALSE(a.dmg.edges.empty());
  std::set<std::pair<int, int>> e;
  for (auto [x, y] : a.dmg.edges) e.insert({x, y});
  for (auto [x, y] : e) {
    EXPECT_TRUE(e.contains({y, x}));
    EXPECT_EQ(a.dmg.nodes[x].facet, a.dmg.nodes[y].facet);
    EXPECT_LT((a.dmg.nodes[x].position - a.dmg.nodes[y].position).norm(), 3 * a.dmg.seed_resolution);
  }
}

TEST(Dmg, AFingerSlidesAllRoundACylindersSide) {
  DmgOptions o;
  o.seed_resolution = 0.006;
  o.normal_threshold = 0.15;  // the original's launch-file value; patches 6 mm apart on r = 30 mm
  const auto a = bake(make_cylinder_mesh(0.03, 0.1, 96), o);
  // Facets: the side and the two caps.
  ASSERT_EQ(a.dmg.facet_normals.size(), 3u);
  std::vector<int> side;
  for (std::size_t i = 0; i < a.dmg.nodes.size(); ++i)
    if (std::abs(a.dmg.nodes[i].normal.z()) < 0.1) side.push_back(int(i));
  ASSERT_GT(side.size(), 20u);
  const int facet = a.dmg.nodes[side[0]].facet;
  for (int i : side) EXPECT_EQ(a.dmg.nodes[i].facet, facet);
  // From one side node the edges reach azimuths all round: no gap wider than 30 degrees.
  std::vector<std::vector<int>> adj(a.dmg.nodes.size());
  for (auto [x, y] : a.dmg.edges) adj[x].push_back(y);
  std::vector<char> seen(a.dmg.nodes.size(), 0);
  std::queue<int> q;
  q.push(side[0]);
  seen[side[0]] = 1;
  std::vector<double> azimuth;
  while (!q.empty()) {
    const int x = q.front();
    q.pop();
    azimuth.push_back(std::atan2(a.dmg.nodes[x].position.y(), a.dmg.nodes[x].position.x()));
    for (int y : adj[x])
      if (!seen[y]) seen[y] = 1, q.push(y);
  }
  std::sort(azimuth.begin(), azimuth.end());
  double gap = azimuth.front() + 2 * std::numbers::pi - azimuth.back();
  for (std::size_t i = 1; i < azimuth.size(); ++i) gap = std::max(gap, azimuth[i] - azimuth[i - 1]);
  EXPECT_LT(gap, 30 * std::numbers::pi / 180);
  EXPECT_TRUE(check_object(a).empty()) << check_object(a).front();
}

TEST(Dmg, ABoxFaceCenterCanBeGraspedAtEveryAngle) {
  // Across x at the face center: the box reaches at most 25 mm (diagonal of 35 x 35 mm) plus the
  // patch offset from the TCP in the y-z plane, less than the 36 mm to the palm, so nothing blocks
  // a full turn. A 60 mm cube would block the diagonal angles (42 mm) and must not pass.
  const auto a = bake(make_box_mesh({0.06, 0.035, 0.035}));
  const auto cube = bake(make_box_mesh({0.06, 0.06, 0.06}));
  for (const auto* obj : {&a, &cube}) {
    bool found = false;
    for (const auto& n : obj->dmg.nodes)
      if (std::abs(n.position.y()) < 0.008 && std::abs(n.position.z()) < 0.008 && n.normal.x() > 0.99) {
        found = true;
        if (obj == &a) EXPECT_EQ(n.angle_count, a.dmg.angle_count());
        else EXPECT_LT(n.angle_count, cube.dmg.angle_count());
      }
    EXPECT_TRUE(found);
  }
}

TEST(Dmg, BadOptionsAreRejected) {
  const auto box = make_box_mesh({0.05, 0.05, 0.05});
  DmgOptions o;
  o.angle_step_deg = 7;
  EXPECT_THROW(build_dmg(box, default_gripper(), o, "box.stl"), Error);
  o = {};
  o.seed_resolution = 0;
  EXPECT_THROW(build_dmg(box, default_gripper(), o, "box.stl"), Error);
}

TEST(Dmg, CheckObjectReportsBrokenGraphs) {
  auto a = bake(make_box_mesh({0.05, 0.07, 0.09}));
  ASSERT_TRUE(check_object(a).empty());
  auto asym = a;
  asym.dmg.edges.pop_back();
  EXPECT_FALSE(check_object(asym).empty());
  auto off = a;
  off.dmg.nodes[0].position += 0.01 * off.dmg.nodes[0].normal;
  EXPECT_FALSE(check_object(off).empty());
  auto wide = a;
  wide.dmg.gripper.max_opening = 0.03;
  EXPECT_FALSE(check_object(wide).empty());
  auto angles = a;
  angles.dmg.nodes[0].first_angle = angles.dmg.angle_count();
  EXPECT_FALSE(check_object(angles).empty());
  auto face = a;
  face.placement.faces[0].normal *= 2;
  EXPECT_FALSE(check_object(face).empty());
}

// The baked grasp graph, as properties over every state and edge of real DMGs.
TEST(GraspGraphTable, EdgesAreReversibleMovesOfTheDmgWithTheirCosts) {
  for (const auto& mesh : {make_box_mesh({0.05, 0.07, 0.09}), make_cylinder_mesh(0.03, 0.1, 32)}) {
    const auto a = bake(mesh);
    const auto& t = a.grasp_graph;
    const auto& d = a.dmg;
    ASSERT_GT(t.size(), 0);
    const int k = d.angle_count();
    const double step = d.angle_step_deg * std::numbers::pi / 180;
    std::map<std::pair<int, int>, double> cost;
    for (int s = 0; s < t.size(); ++s)
      for (int e = t.offsets[s]; e < t.offsets[s + 1]; ++e) {
        const int u = t.targets[e], na = t.state_node[s], nb = t.state_node[u];
        if (t.moves[e] == formats::GraspMoveKind::Rotation) {
          EXPECT_EQ(na, nb);
          const int da = ((t.state_angle[u] - t.state_angle[s]) % k + k) % k;
          EXPECT_TRUE(da == 1 || da == k - 1);
          EXPECT_NEAR(t.costs[e], step * t.rotation_weight, 1e-12);
        } else {
          EXPECT_EQ(t.state_angle[s], t.state_angle[u]);
          EXPECT_TRUE(std::find(d.edges.begin(), d.edges.end(), std::array<int, 2>{na, nb}) != d.edges.end());
          EXPECT_NEAR(t.costs[e], (d.nodes[na].position - d.nodes[nb].position).norm(), 1e-12);
        }
        EXPECT_GT(t.costs[e], 0);
        cost[{s, u}] = t.costs[e];
      }
    for (const auto& [e, c] : cost) {
      ASSERT_TRUE(cost.contains({e.second, e.first})) << e.first << " -> " << e.second;
      EXPECT_DOUBLE_EQ(cost.at({e.second, e.first}), c);
    }
    // The snap index: each state's TCP sits between its contacts with y along the node's normal.
    for (int s = 0; s < t.size(); ++s) {
      const auto& n = d.nodes[t.state_node[s]];
      const double* c = &t.tcp[7 * std::size_t(s)];
      EXPECT_NEAR((Eigen::Vector3d(c[0], c[1], c[2]) - 0.5 * (n.position + n.opposite_point)).norm(), 0, 1e-12);
      const Eigen::Matrix3d r = Eigen::Quaterniond(c[6], c[3], c[4], c[5]).toRotationMatrix();
      EXPECT_NEAR(r.col(1).dot(n.normal), 1, 1e-9);
      EXPECT_NEAR(t.opening[s], (n.position - n.opposite_point).norm(), 1e-12);
    }
    EXPECT_TRUE(check_object(a).empty()) << check_object(a).front();
  }
}

TEST(GraspGraphTable, CheckObjectRefusesAGraphThatDisagreesWithTheDmg) {
  const auto a = bake(make_box_mesh({0.05, 0.07, 0.09}));
  ASSERT_TRUE(check_object(a).empty());
  auto expect_refused = [&](const formats::ObjectArtifact& b, const std::string& what) {
    const auto p = check_object(b);
    ASSERT_FALSE(p.empty()) << what;
    EXPECT_NE(p.front().find("grasp_graph"), std::string::npos) << p.front();
  };
  int translation = -1;
  for (std::size_t e = 0; e < a.grasp_graph.moves.size() && translation < 0; ++e)
    if (a.grasp_graph.moves[e] == formats::GraspMoveKind::Translation) translation = int(e);
  ASSERT_GE(translation, 0);
  auto b = a;
  b.grasp_graph.costs[translation] *= 1.5;
  expect_refused(b, "a cost changed");
  b = a;
  b.grasp_graph.moves[translation] = formats::GraspMoveKind::Rotation;
  expect_refused(b, "a translation called a rotation");
  b = a;
  b.grasp_graph.targets[0] = b.grasp_graph.targets[0] == 0 ? 1 : 0;
  expect_refused(b, "an edge retargeted");
  b = a;
  b.grasp_graph.tcp[0] += 0.001;
  expect_refused(b, "the snap index moved");
  b = a;
  b.grasp_graph.state_angle[0] = (b.grasp_graph.state_angle[0] + 1) % a.dmg.angle_count();
  expect_refused(b, "a state's angle");
  b = a;
  b.grasp_graph.rotation_weight = 0;
  expect_refused(b, "zero rotation weight");
  // Drop the last state's edges (and their reverses elsewhere would dangle): missing edges.
  b = a;
  const int s = b.grasp_graph.size() - 1;
  const int drop = b.grasp_graph.offsets[s + 1] - b.grasp_graph.offsets[s];
  ASSERT_GT(drop, 0);
  b.grasp_graph.targets.resize(b.grasp_graph.targets.size() - drop);
  b.grasp_graph.costs.resize(b.grasp_graph.targets.size());
  b.grasp_graph.moves.resize(b.grasp_graph.targets.size());
  b.grasp_graph.offsets.back() = b.grasp_graph.offsets[s];
  expect_refused(b, "a state's edges dropped");
  b = a;
  b.grasp_graph = {};
  expect_refused(b, "no graph");
}

}  // namespace
}  // namespace dmgplace::tools
