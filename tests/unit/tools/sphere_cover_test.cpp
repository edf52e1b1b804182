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
