// The placement planner's parts on synthetic inputs: the object's sphere cover, the search space,
// the MCTS hierarchy, the samples' reward and the objective.
#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/triangle_distance.hpp"
#include "dmgplace/runtime/collision/object_spheres.hpp"
#include "dmgplace/runtime/placement/goal_validator.hpp"
#include "dmgplace/runtime/placement/objective.hpp"
#include "dmgplace/runtime/placement/placement_tree.hpp"
#include "fixtures.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;

namespace {

Eigen::Vector3d random_surface_point(const TriMesh& m, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> tri(0, int(m.triangles.rows()) - 1);
  std::uniform_real_distribution<double> u(0, 1);
  const int t = tri(rng);
  double a = u(rng), b = u(rng);
  if (a + b > 1) a = 1 - a, b = 1 - b;
  const Eigen::Vector3d p0 = m.vertices.row(m.triangles(t, 0)), p1 = m.vertices.row(m.triangles(t, 1)),
                        p2 = m.vertices.row(m.triangles(t, 2));
  return p0 + a * (p1 - p0) + b * (p2 - p0);
}

bool covered(const SphereSet& s, const Eigen::Vector3d& p) {
  for (std::size_t i = 0; i < s.centers.size(); ++i)
    if ((s.centers[i] - p).norm() <= s.radii[i] + 1e-12) return true;
  return false;
}

formats::ObjectArtifact box_object() {
  formats::ObjectArtifact o;
  o.mesh = test::box_mesh(Eigen::Vector3d(0.10, 0.06, 0.04));
  o.mass.com = Eigen::Vector3d::Zero();
  o.placement = test::placement_faces(o.mesh, o.mass.com);
  return o;
}

// A 0.4 x 0.3 m region at z = 0.5 on 2 cm cells with a hole in the middle.
formats::PlacementRegion region_with_hole() {
  formats::PlacementRegion r;
  r.height = 0.5;
  r.resolution = 0.02;
  r.origin = Eigen::Vector2d(1.0, -0.2);
  r.width = 20;
  r.depth = 15;
  r.mask.assign(std::size_t(r.width * r.depth), 1);
  r.free_height.assign(r.mask.size(), 0.3f);
  for (int j = 5; j < 10; ++j)
    for (int i = 8; i < 12; ++i) r.mask[std::size_t(i + r.width * j)] = 0;
  r.area = double(r.cell_count()) * r.resolution * r.resolution;
  return r;
}

}  // namespace

TEST(ObjectSpheres, CoverContainsTheSurfaceAndTheInside) {
  for (const TriMesh& m :
       {test::box_mesh(Eigen::Vector3d(0.1, 0.05, 0.03)), test::bottle_mesh(), test::eraser_mesh()}) {
    const SphereSet s = cover_object(m, 8);
    ASSERT_FALSE(s.centers.empty());
    std::mt19937_64 rng(5);
    for (int k = 0; k < 3000; ++k) ASSERT_TRUE(covered(s, random_surface_point(m, rng)));
    // Interior points: between two surface points along a line through the inside.
    const Eigen::Vector3d c = m.vertices.colwise().mean().transpose();
    for (int k = 0; k < 300; ++k) {
      const Eigen::Vector3d p = random_surface_point(m, rng);
      const Eigen::Vector3d x = c + 0.9 * (p - c);
      if (inside_mesh(m, x)) {
        ASSERT_TRUE(covered(s, x));
      }
    }
  }
}

// cover_object's lattice only tests the triangles near each cube and on each inside ray's line;
// every cube must get the answer of testing all triangles (the definition, written out here).
TEST(ObjectSpheres, CoverEqualsTestingEveryTriangle) {
  TriMesh tilted = test::bottle_mesh();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (Eigen::Index v = 0; v < tilted.vertices.rows(); ++v)
    tilted.vertices.row(v) = (r * tilted.vertices.row(v).transpose()).transpose();
  for (const TriMesh& m :
       {test::box_mesh(Eigen::Vector3d(0.1, 0.05, 0.03)), test::bottle_mesh(), test::eraser_mesh(), tilted})
    for (int cells : {1, 3, 8, 13}) {
      const Eigen::Vector3d lo = m.vertices.colwise().minCoeff().transpose(),
                            hi = m.vertices.colwise().maxCoeff().transpose();
      const double cell = std::max((hi - lo).maxCoeff() / cells, 1e-4), radius = std::sqrt(3.0) / 2.0 * cell;
      const Eigen::Array3i n = ((hi - lo) / cell).array().ceil().cast<int>().max(1);
      const Eigen::Vector3d start = 0.5 * (lo + hi) - 0.5 * cell * n.cast<double>().matrix();
      std::vector<Eigen::Vector3d> expected;
      for (int k = 0; k < n.z(); ++k)
        for (int j = 0; j < n.y(); ++j)
          for (int i = 0; i < n.x(); ++i) {
            const Eigen::Vector3d c = start + cell * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
            bool near = false;
            for (Eigen::Index t = 0; t < m.triangles.rows() && !near; ++t)
              near = (formats::closest_point_on_triangle(c, m.vertices.row(m.triangles(t, 0)).transpose(),
                                                         m.vertices.row(m.triangles(t, 1)).transpose(),
                                                         m.vertices.row(m.triangles(t, 2)).transpose()) -
                      c)
                         .squaredNorm() <= radius * radius;
            if (near || inside_mesh(m, c)) expected.push_back(c);
          }
      const SphereSet s = cover_object(m, cells);
      ASSERT_EQ(s.centers.size(), expected.size()) << cells << " cells";
      for (std::size_t k = 0; k < expected.size(); ++k) {
        EXPECT_EQ(s.centers[k], expected[k]);
        EXPECT_EQ(s.radii[k], radius);
      }
    }
}

TEST(SearchSpace, PosesRestOnTheRegionAndCropToTheVolume) {
  const auto obj = box_object();
  const std::vector<formats::PlacementRegion> regions{region_with_hole()};
  const Eigen::AlignedBox3d everything(Eigen::Vector3d(-10, -10, 0), Eigen::Vector3d(10, 10, 2));
  const SearchSpace space(obj, regions, everything);
  ASSERT_EQ(space.face_count(), 6);
  ASSERT_EQ(space.region_count(), 1);
  EXPECT_EQ(space.supported_cells(0, space.full_range(0)), 20 * 15 - 20);
  for (int f = 0; f < space.face_count(); ++f) {
    const Eigen::Isometry3d x = space.pose(f, 0, Eigen::Vector2d(1.1, -0.1), 0.7);
    for (const auto& v : space.face(f).polygon) EXPECT_NEAR((x * v).z(), 0.5, 1e-9);
    EXPECT_TRUE((x * obj.mass.com).head<2>().isApprox(Eigen::Vector2d(1.1, -0.1), 1e-12));
    for (int k = 0; k < obj.mesh.vertices.rows(); ++k)
      EXPECT_GE((x * obj.mesh.vertices.row(k).transpose()).z(), 0.5 - 1e-9);
    EXPECT_TRUE(space.stable(f, 0, x));
    // Over the hole it is not supported.
    EXPECT_FALSE(space.stable(f, 0, space.pose(f, 0, Eigen::Vector2d(1.2, -0.05), 0)));
  }
  // A volume covering only the left half keeps only that half's cells; one above it none.
  const SearchSpace left(obj, regions, Eigen::AlignedBox3d(Eigen::Vector3d(0, -1, 0.4), Eigen::Vector3d(1.2, 1, 0.8)));
  EXPECT_EQ(left.supported_cells(0, left.full_range(0)), 10 * 15 - 2 * 5);  // two hole columns are in the left half
  const SearchSpace above(obj, regions, Eigen::AlignedBox3d(Eigen::Vector3d(0, -1, 0.6), Eigen::Vector3d(2, 1, 0.8)));
  EXPECT_EQ(above.region_count(), 0);
}

TEST(PlacementTree, RolloutsStayInsideTheirNodeAndOnSupport) {
  const auto obj = box_object();
  const std::vector<formats::PlacementRegion> regions{region_with_hole()};
  const SearchSpace space(obj, regions, Eigen::AlignedBox3d(Eigen::Vector3d(-10, -10, 0), Eigen::Vector3d(10, 10, 2)));
  PlacementTree tree(space, 4, 0.5);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  for (int it = 0; it < 3000; ++it) {
    const int n = tree.select(rng);
    ASSERT_GE(n, 0);
    const auto& cell = tree.node(n).cell;
    const PlacementSample s = tree.rollout(n, rng);
    ASSERT_GE(s.face, 0);
    ASSERT_GE(s.region, 0);
    if (cell.face >= 0) {
      EXPECT_EQ(s.face, cell.face);
    }
    EXPECT_TRUE(space.supported(s.region, s.xy));
    EXPECT_GE(s.theta, cell.t0);
    EXPECT_LE(s.theta, cell.t1);
    if (cell.level >= 2) {
      const auto& reg = space.region(s.region);
      const Eigen::Vector2d c = (s.xy - reg.origin) / reg.resolution;
      EXPECT_GE(c.x(), cell.cells.i0);
      EXPECT_LE(c.x(), cell.cells.i1);
      EXPECT_GE(c.y(), cell.cells.j0);
      EXPECT_LE(c.y(), cell.cells.j1);
    }
    // Reward poses near one corner so the search has something to learn.
    tree.backpropagate(n, (s.xy - Eigen::Vector2d(1.0, -0.2)).norm() < 0.1 ? 1.0 : 0.1 * u(rng));
  }
  EXPECT_EQ(tree.node(0).visits, 3000);
  for (int n = 0; n < tree.size(); ++n) {
    const auto& node = tree.node(n);
    int child_visits = 0;
    for (int c : node.children) {
      child_visits += tree.node(c).visits;
      EXPECT_EQ(tree.node(c).cell.level, node.cell.level + 1);
      EXPECT_NEAR(tree.node(c).cell.t1 - tree.node(c).cell.t0,
                  node.cell.level >= 2 ? (node.cell.t1 - node.cell.t0) / 4 : node.cell.t1 - node.cell.t0, 1e-12);
    }
    EXPECT_LE(child_visits, node.visits);
    EXPECT_LE(node.children.size(), node.cell.level == 0 ? 6u : node.cell.level == 1 ? 1u : 16u);
  }
  // UCB concentrates visits: the rewarding corner's face-region subtree holds most of them.
  EXPECT_GT(tree.size(), 50);
}

// Every combination of the five constraints, before and after a first solution.
TEST(GoalReward, RelaxedUntilAFirstSolutionThenOnlyGoalsCount) {
  const PlacementOptions o;
  auto check = [](int bits) {
    GoalCheck c;
    c.stable = bits & 1, c.object_free = bits & 2, c.improves = bits & 4, c.reachable = bits & 8,
    c.arm_free = bits & 16;
    return c;
  };
  for (int bits = 0; bits < 32; ++bits) {
    const GoalCheck c = check(bits);
    const double before = c.reward(o, false), after = c.reward(o, true);
    EXPECT_EQ(before == 1.0, c.valid()) << bits;
    EXPECT_EQ(after, c.valid() ? 1.0 : 0.0) << "after a solution only a new goal earns: " << bits;
    EXPECT_GE(before, 0.0);
    EXPECT_LE(before, 1.0);
    // Monotone: satisfying one more constraint never lowers the relaxed reward.
    for (int k = 0; k < 5; ++k) {
      if (!(bits & (1 << k))) {
        EXPECT_GE(check(bits | (1 << k)).reward(o, false), before) << bits << " + bit " << k;
      }
    }
    if (bits != 0 && bits != 4) {  // "improves" alone counts only for a placement
      EXPECT_GT(before, 0.0) << "before a solution every constraint met earns: " << bits;
    }
  }
  // The plateau the relaxation made after a first solution: a feasible, reached pose that does not
  // improve earned nearly as much as a goal.
  EXPECT_GT(check(1 | 2 | 8 | 16).reward(o, false), 0.6);
}

TEST(Objective, DepthAndDistanceTermsAndTheirGradients) {
  const auto obj = box_object();
  EnvironmentModel env;
  std::vector<ObjectiveTerm> terms(2);
  terms[0].kind = ObjectiveTerm::Kind::Depth;
  terms[0].vector = Eigen::Vector3d(2, 0, 0);  // normalised by the objective
  terms[1].kind = ObjectiveTerm::Kind::Distance;
  terms[1].weight = 0.5;
  terms[1].vector = Eigen::Vector3d(1, 1, 0.5);
  const Objective f(terms, env, obj, {});
  Eigen::Isometry3d x = Eigen::Translation3d(0.3, 0.2, 0.5) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d com = x * obj.mass.com;
  EXPECT_NEAR(f.value(x), com.x() - 0.5 * (com - terms[1].vector).norm(), 1e-12);
  const Eigen::Vector3d g = f.gradient(x);
  const Eigen::Vector3d to_target = (terms[1].vector - com).normalized();
  EXPECT_NEAR(g.x(), 1 + 0.5 * to_target.x(), 1e-5);
  EXPECT_NEAR(g.y(), 0.5 * to_target.y(), 1e-5);
  EXPECT_NEAR(g.z(), 0, 1e-9);  // turning about the COM changes neither term
  EXPECT_TRUE((f.moved(x, Eigen::Vector3d(0, 0, 1.0)) * obj.mass.com).isApprox(com, 1e-12));
  // Bad terms are refused with the term named.
  terms[0].vector.setZero();
  EXPECT_THROW(Objective(terms, env, obj, {}), dmgplace::Error);
  std::vector<ObjectiveTerm> clearance(1);
  EXPECT_THROW(Objective(clearance, env, obj, {}), dmgplace::Error);  // no clearance field
}
