// The sphere cover's inner balls (inner_radius), as the fast layer proves collisions with them.
#include <gtest/gtest.h>

#include <cmath>

#include "collision_fixtures.hpp"
#include "dmgplace/formats/winding_number.hpp"

using namespace dmgplace;
using namespace dmgplace::runtime;
using namespace dmgplace::test::collision;

// Every sphere's inner ball lies inside its link's geometry: points on and in the ball (Fibonacci
// directions at three depths) are inside by the winding number or the primitive's distance.
TEST(SphereCover, InnerBallsLieInsideTheLinkGeometry) {
  Arm arm = built_in_arm();
  int with_ball = 0;
  for (const auto& s : arm.spheres) {
    const auto& shapes = arm.model.links[std::size_t(s.link)].collision;
    const double r = inner_radius(shapes, s.center);
    ASSERT_GE(r, 0.0);
    if (r <= 0) continue;
    ++with_ball;
    for (int k = 0; k < 64; ++k)
      for (const double depth : {0.999, 0.7, 0.3}) {
        const double z = 1 - 2 * (k + 0.5) / 64, ph = k * M_PI * (3 - std::sqrt(5.0));
        const Eigen::Vector3d x =
            s.center +
            depth * r * Eigen::Vector3d(std::sqrt(1 - z * z) * std::cos(ph), std::sqrt(1 - z * z) * std::sin(ph), z);
        bool inside = false;
        for (const auto& sh : shapes)
          inside |= sh.type == ShapeType::Mesh ? winding_number(sh.mesh, sh.origin.inverse() * x) > 0.5
                                               : shape_signed_distance(sh, x) <= 0;
        ASSERT_TRUE(inside) << arm.model.links[std::size_t(s.link)].name << " ball " << r << " at "
                            << s.center.transpose();
      }
  }
  EXPECT_GT(with_ball, int(arm.spheres.size()) / 2) << "most sphere centers lie inside their link";
}
