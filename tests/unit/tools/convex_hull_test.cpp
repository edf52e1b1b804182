// The hulls bake-robot stores beside link meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "dmgplace/formats/shape_table.hpp"
#include "dmgplace/runtime/geometry/convex_gap.hpp"
#include "dmgplace/tools/geometry/convex_hull.hpp"

using namespace dmgplace;

namespace {
TriMesh cloud(std::mt19937_64& rng, int n, double flat_z = -1) {
  std::normal_distribution<double> g(0, 1);
  TriMesh m;
  m.vertices.resize(n, 3);
  for (int i = 0; i < n; ++i)
    m.vertices.row(i) = Eigen::RowVector3d(0.05 * g(rng), 0.03 * g(rng), flat_z >= 0 ? flat_z : 0.1 * g(rng));
  m.triangles.resize(1, 3);
  m.triangles << 0, 1, 2;
  return m;
}
}  // namespace

// Along every direction the hull's farthest vertex is the mesh's farthest vertex, and the hull
// passes the artifact check (closed, outward, every vertex inside).
TEST(ConvexHull, SupportsEqualTheMeshsAndTheArtifactCheckPasses) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0, 1);
  for (int n : {4, 50, 2000}) {
    const TriMesh m = cloud(rng, n);
    const RowMatrixX3i hull = tools::convex_hull_triangles(m);
    ASSERT_GE(hull.rows(), 4) << n;
    EXPECT_FALSE(formats::hull_problem(m, hull).has_value()) << *formats::hull_problem(m, hull);
    for (int k = 0; k < 500; ++k) {
      const Eigen::Vector3d d(g(rng), g(rng), g(rng));
      const double all = (m.vertices * d).maxCoeff();
      double on_hull = -1e300;
      for (Eigen::Index i = 0; i < hull.size(); ++i) on_hull = std::max(on_hull, m.vertices.row(hull.data()[i]).dot(d));
      EXPECT_DOUBLE_EQ(on_hull, all) << n;
    }
  }
}

TEST(ConvexHull, FlatOrTinyInputHasNoHull) {
  std::mt19937_64 rng(6);
  EXPECT_EQ(tools::convex_hull_triangles(cloud(rng, 100, 0.02)).rows(), 0) << "coplanar";
  EXPECT_EQ(tools::convex_hull_triangles(cloud(rng, 3)).rows(), 0) << "three points";
}

// The runtime climbs a stored hull's edges for its supports: on CGAL's hulls (as bake-robot
// stores them) every climb, from any start, ends at the mesh's farthest vertex.
TEST(ConvexHull, ClimbsOverAStoredHullFindTheMeshsFarthestVertex) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1);
  for (int n : {4, 50, 2000}) {
    Shape shape;
    shape.type = ShapeType::Mesh;
    shape.mesh = cloud(rng, n);
    shape.hull = tools::convex_hull_triangles(shape.mesh);
    const auto solid = runtime::ConvexSolid::of(shape);
    ASSERT_TRUE(solid.has_value());
    std::vector<int> used(shape.hull.data(), shape.hull.data() + shape.hull.size());
    std::sort(used.begin(), used.end());
    const int points = int(std::unique(used.begin(), used.end()) - used.begin());
    std::uniform_int_distribution<int> any(-1, points - 1);  // a hull point, or none
    for (int k = 0; k < 500; ++k) {
      const Eigen::Vector3d d(g(rng), g(rng), g(rng));
      int start = any(rng);
      EXPECT_DOUBLE_EQ(solid->support(d, start).dot(d), (shape.mesh.vertices * d).maxCoeff()) << n;
    }
  }
}

// A box's points with grids over its faces, in a shuffled order: the hull keeps the corners only,
// two triangles per face, each face split through its corner listed first. CGAL on its own splits
// flat faces however its internals met them (which varied with the command line's length) and
// keeps grid points it met first.
TEST(ConvexHull, FlatFacetsAreSplitFromTheirFirstListedCornerAndOnlyCornersRemain) {
  std::mt19937_64 rng(8);
  const Eigen::Vector3d half(0.1, 0.07, 0.05);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      for (int k = 0; k <= 4; ++k) {
        const Eigen::Vector3d u(i / 2.0 - 1, j / 2.0 - 1, k / 2.0 - 1);
        if (u.cwiseAbs().maxCoeff() == 1) pts.push_back(u.cwiseProduct(half));  // on the surface only
      }
  for (int trial = 0; trial < 10; ++trial) {
    std::shuffle(pts.begin(), pts.end(), rng);
    TriMesh m;
    m.vertices.resize(long(pts.size()), 3);
    for (std::size_t i = 0; i < pts.size(); ++i) m.vertices.row(long(i)) = pts[i].transpose();
    m.triangles.resize(1, 3);
    m.triangles << 0, 1, 2;
    const RowMatrixX3i hull = tools::convex_hull_triangles(m);
    ASSERT_EQ(hull.rows(), 12) << trial;
    EXPECT_FALSE(formats::hull_problem(m, hull).has_value());
    for (Eigen::Index f = 0; f < hull.rows(); ++f) {
      const Eigen::Vector3d a = m.vertices.row(hull(f, 0)), b = m.vertices.row(hull(f, 1)),
                            c = m.vertices.row(hull(f, 2));
      for (const Eigen::Vector3d& p : {a, b, c}) EXPECT_TRUE(p.cwiseAbs().isApprox(half)) << "not a corner";
      // The face's plane: the axis on which all three sit at the same extreme.
      const Eigen::Vector3d n = (b - a).cross(c - a);
      int axis = 0;
      n.cwiseAbs().maxCoeff(&axis);
      int first = int(m.vertices.rows());
      for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
        if (m.vertices(i, axis) == a[axis] && m.vertices.row(i).cwiseAbs().isApprox(half.transpose()))
          first = std::min(first, int(i));
      EXPECT_TRUE(hull(f, 0) == first || hull(f, 1) == first || hull(f, 2) == first) << "face " << f;
      EXPECT_GT(n.dot(a), 0) << "inward";
    }
  }
}

// The artifact check's "every vertex inside every face", against a scan of every vertex: a hull of
// part of the points leaves some outside, and a point of the whole hull's inside moved onto a
// face's plane and then out by twice the tolerance or in by half of it is told apart as the scan
// tells it.
TEST(ConvexHull, TheArtifactCheckFindsVerticesOutsideAsAScanOfAllOfThemDoes) {
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int> part(4, 60);
  int outside = 0, inside = 0;
  for (int trial = 0; trial < 200; ++trial) {
    TriMesh m = cloud(rng, 400);
    RowMatrixX3i hull;
    if (trial % 2 == 0) {
      TriMesh first = m;
      first.vertices.conservativeResize(part(rng), 3);
      hull = tools::convex_hull_triangles(first);
    } else {
      hull = tools::convex_hull_triangles(m);
      std::vector<char> on_hull(std::size_t(m.vertices.rows()), 0);
      for (Eigen::Index i = 0; i < hull.size(); ++i) on_hull[std::size_t(hull.data()[i])] = 1;
      const Eigen::Index moved = Eigen::Index(std::find(on_hull.begin(), on_hull.end(), 0) - on_hull.begin());
      const Eigen::Index f = Eigen::Index(rng() % std::uint64_t(hull.rows()));
      const Eigen::Vector3d a = m.vertices.row(hull(f, 0)), b = m.vertices.row(hull(f, 1)),
                            c = m.vertices.row(hull(f, 2));
      const Eigen::Vector3d u = (b - a).cross(c - a).normalized();
      const double tol = 1e-9 * std::max(1.0, m.vertices.cwiseAbs().maxCoeff());
      m.vertices.row(moved) = ((a + b + c) / 3 + (trial % 4 == 1 ? 2.0 : -0.5) * tol * u).transpose();
    }
    if (hull.rows() < 4) continue;
    const double tol = 1e-9 * std::max(1.0, m.vertices.cwiseAbs().maxCoeff());
    bool scan_outside = false;
    for (Eigen::Index f = 0; f < hull.rows(); ++f) {
      const Eigen::Vector3d a = m.vertices.row(hull(f, 0)), b = m.vertices.row(hull(f, 1)),
                            c = m.vertices.row(hull(f, 2));
      const Eigen::Vector3d n = (b - a).cross(c - a);
      if (!(n.norm() > 0)) continue;
      scan_outside |= ((m.vertices.rowwise() - a.transpose()) * (n / n.norm())).maxCoeff() > tol;
    }
    const auto problem = formats::hull_problem(m, hull);
    const bool said_outside = problem && problem->find("outside convex hull face") != std::string::npos;
    EXPECT_EQ(said_outside, scan_outside) << "trial " << trial << ": " << problem.value_or("no problem");
    (scan_outside ? outside : inside)++;
  }
  EXPECT_GT(outside, 50);
  EXPECT_GT(inside, 20);
}
