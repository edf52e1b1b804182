// The runtime view of an environment artifact: interpolating grids and regions.
#include <gtest/gtest.h>

#include "analytic_sdf.hpp"
#include "dmgplace/runtime/environment/environment_model.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

using namespace dmgplace;

TEST(EnvironmentModel, LoadsBakedFieldsAsGridsWithGradients) {
  formats::EnvironmentArtifact env;
  Shape table;
  table.type = ShapeType::Box;
  table.size = Eigen::Vector3d(0.6, 0.6, 0.04);
  table.origin.translation() = Eigen::Vector3d(0, 0, 0.38);
  env.scene.objects.push_back({"table", {table}});
  env.volume = Eigen::AlignedBox3d(Eigen::Vector3d(-0.25, -0.25, 0.3), Eigen::Vector3d(0.25, 0.25, 0.7));
  test::bake_environment(env);
  test::TempDir dir;
  formats::save_environment(env, dir / "e.h5");
  const runtime::EnvironmentModel m = runtime::make_environment_model(formats::load_environment(dir / "e.h5"));
  ASSERT_TRUE(m.sdf && m.clearance);
  EXPECT_TRUE(m.sdf_signed);
  EXPECT_DOUBLE_EQ(m.sdf_band, 0.10);
  Eigen::Vector3d grad;
  // 3 cm above the table top (z = 0.40): distance 0.03, gradient straight up.
  EXPECT_NEAR(m.sdf->sample(Eigen::Vector3d(0.01, 0.02, 0.43), grad), 0.03, 1e-4);
  EXPECT_NEAR(grad.z(), 1.0, 1e-3);
  EXPECT_NEAR(grad.head<2>().norm(), 0.0, 1e-3);
  // Inside the board: negative, matching the exact box distance.
  EXPECT_NEAR(m.sdf->sample(Eigen::Vector3d(0, 0, 0.385)), test::scene_signed_distance(env.scene, {0, 0, 0.385}),
              0.005);
  // Nothing above the table: clearance is the band everywhere over it.
  EXPECT_NEAR(m.clearance->sample(Eigen::Vector3d(0, 0, 0.45)), m.clearance_band, 1e-6);
  ASSERT_FALSE(m.regions.empty());
  double area = 0;
  for (const auto& r : m.regions) {
    EXPECT_NEAR(r.height, 0.40, 1e-9);
    area += r.area;
  }
  EXPECT_NEAR(area, 0.5 * 0.5, 1e-9);
}
