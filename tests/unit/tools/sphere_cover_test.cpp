#include <gtest/gtest.h>

#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"
#include "test_support.hpp"

using namespace dmgplace;

// The cover of every link of the built-in arm holds every point of a sampling finer than the one
// it was built from.
TEST(SphereCover, EverySamplePointOfEveryLinkIsInsideASphere) {
  const auto dir = test::source_dir() / "datasets/robots/dmgarm";
  const RobotModel model = tools::read_urdf(dir / "dmgarm.urdf");
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    const auto& shapes = model.links[l].collision;
    if (shapes.empty()) continue;
    const std::vector<tools::Sphere> spheres = tools::cover_with_spheres(shapes);
    ASSERT_FALSE(spheres.empty()) << model.links[l].name;
    EXPECT_LE(spheres.size(), 32u);
    for (const auto& p : tools::sample_solid(shapes, 0.0025)) {
      bool inside = false;
      for (const auto& s : spheres) inside |= (p - s.center).norm() <= s.radius + 1e-9;
      ASSERT_TRUE(inside) << model.links[l].name << " point " << p.transpose();
    }
  }
}

// A corner tetrahedron's smallest enclosing ball is its long face's circumball (center (1,1,1)/3,
// radius sqrt(2/3)), smaller than the ball about its bounding box's center (sqrt(3)/2): one
// sphere must come near the former and still hold every sample.
TEST(SphereCover, OneSphereComesNearTheSmallestEnclosingBall) {
  Shape tet;
  tet.type = ShapeType::Mesh;
  tet.size = Eigen::Vector3d::Ones();
  tet.mesh.vertices.resize(4, 3);
  tet.mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  tet.mesh.triangles.resize(4, 3);
  tet.mesh.triangles << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  tools::SphereCoverOptions one;
  one.max_spheres = 1;
  one.sample_spacing = 0.02;
  const std::vector<tools::Sphere> spheres = tools::cover_with_spheres({tet}, one);
  ASSERT_EQ(spheres.size(), 1u);
  const double smallest = std::sqrt(2.0 / 3.0);
  EXPECT_LE(spheres[0].radius - one.sample_spacing, 1.01 * smallest);
  EXPECT_LT((spheres[0].center - Eigen::Vector3d::Constant(1.0 / 3.0)).norm(), 0.05);
  for (const auto& p : tools::sample_solid({tet}, 0.01))
    ASSERT_LE((p - spheres[0].center).norm(), spheres[0].radius + 1e-9) << p.transpose();
}
