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
