// The v2 environment artifact: fields and regions survive a round trip, and validation catches
// broken invariants.
#include <gtest/gtest.h>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/environment/bake_environment.hpp"
#include "test_support.hpp"

using namespace dmgplace;

namespace {

formats::EnvironmentArtifact baked_box_on_floor() {
  formats::EnvironmentArtifact env;
  const auto box = test::box_shape;
  env.scene.objects.push_back({"floor", {box({1, 1, 0.02}, {0, 0, -0.01})}});
  env.scene.objects.push_back({"box", {box({0.1, 0.1, 0.1}, {0, 0, 0.05})}});
  env.volume = Eigen::AlignedBox3d(Eigen::Vector3d(-0.2, -0.2, 0), Eigen::Vector3d(0.2, 0.2, 0.3));
  tools::EnvironmentBakeOptions o;
  o.resolution = 0.02;
  o.regions.split_size = 1.0;  // the floor stays one region
  tools::bake_environment(env, o);
  return env;
}

}  // namespace

TEST(EnvArtifact, FieldsAndRegionsRoundTripAndValidate) {
  test::TempDir dir;
  const auto env = baked_box_on_floor();
  ASSERT_TRUE(formats::check_environment(env).empty()) << formats::check_environment(env).at(0);
  ASSERT_EQ(env.regions.size(), 2u);
  formats::save_environment(env, dir / "e.h5");
  const auto back = formats::load_environment(dir / "e.h5");
  EXPECT_EQ(back.sdf.values, env.sdf.values);
  EXPECT_EQ(back.sdf.dims, env.sdf.dims);
  EXPECT_EQ(back.sdf.origin, env.sdf.origin);
  EXPECT_EQ(back.sdf.band, env.sdf.band);
  EXPECT_TRUE(back.sdf_signed);
  EXPECT_EQ(back.clearance.values, env.clearance.values);
  ASSERT_EQ(back.regions.size(), env.regions.size());
  for (std::size_t i = 0; i < env.regions.size(); ++i) {
    EXPECT_EQ(back.regions[i].mask, env.regions[i].mask);
    EXPECT_EQ(back.regions[i].free_height, env.regions[i].free_height);
    EXPECT_EQ(back.regions[i].height, env.regions[i].height);
    EXPECT_EQ(back.regions[i].area, env.regions[i].area);
    EXPECT_EQ(back.regions[i].origin, env.regions[i].origin);
  }
  EXPECT_TRUE(formats::validate_artifact(dir / "e.h5").empty());
}

TEST(EnvArtifact, ValidationReportsBrokenGridsAndRegions) {
  const auto good = baked_box_on_floor();
  auto nan = good;
  nan.sdf.values[5] = NAN;
  EXPECT_EQ(formats::check_environment(nan).size(), 1u);

  auto small = good;  // a grid that no longer covers V
  small.clearance.dims[2] = 2;
  small.clearance.values.resize(small.clearance.size());
  ASSERT_EQ(formats::check_environment(small).size(), 1u);
  EXPECT_NE(formats::check_environment(small)[0].find("cover"), std::string::npos);

  auto floating = good;  // a region lifted 10 cm into the air: no surface under its cells
  floating.regions[0].height += 0.1;
  ASSERT_EQ(formats::check_environment(floating).size(), 1u);
  EXPECT_NE(formats::check_environment(floating)[0].find("no surface"), std::string::npos);

  auto outside = good;  // a region moved out of V
  outside.regions[0].origin.x() += 1.0;
  bool found = false;
  for (const auto& p : formats::check_environment(outside)) found |= p.find("outside the volume") != std::string::npos;
  EXPECT_TRUE(found);

  auto area = good;
  area.regions[1].area *= 2;
  EXPECT_EQ(formats::check_environment(area).size(), 1u);
}

TEST(EnvArtifact, BadBakeOptionsNameTheOption) {
  formats::EnvironmentArtifact env = baked_box_on_floor();
  tools::EnvironmentBakeOptions o;
  o.resolution = -1;
  try {
    tools::bake_environment(env, o);
    FAIL() << "negative resolution accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--resolution"), std::string::npos) << e.what();
  }
  o = tools::EnvironmentBakeOptions{};
  o.resolution = 1e-5;  // 10 um over 0.5 m^3: far too many samples
  EXPECT_THROW(tools::bake_environment(env, o), Error);
}

// The clearance objective must keep rising across the whole target volume: by default the field
// is clamped at V's diagonal, not at a fixed band that flattens it a few decimetres from a wall.
TEST(EnvArtifact, ClearanceKeepsRisingAcrossTheWholeVolume) {
  formats::EnvironmentArtifact env;
  const auto box = test::box_shape;
  env.scene.objects.push_back({"floor", {box({3.2, 1, 0.02}, {0, 0, -0.01})}});
  env.scene.objects.push_back({"wall", {box({0.02, 1, 1}, {-1.5, 0, 0.5})}});  // its face at x = -1.49
  env.volume = Eigen::AlignedBox3d(Eigen::Vector3d(-1.45, -0.4, 0), Eigen::Vector3d(1.45, 0.4, 0.5));
  tools::EnvironmentBakeOptions o;
  o.resolution = 0.02;
  tools::bake_environment(env, o);
  const auto& f = env.clearance;
  EXPECT_NEAR(f.band, env.volume.diagonal().norm(), 1e-12);
  double previous = -1;
  for (double x = -1.4; x <= 1.4; x += 0.1) {
    // The node nearest (x, 0, 0.1): the distance to the wall, up to a cell of rounding.
    const Eigen::Vector3d p(x, 0, 0.1);
    std::array<int, 3> i{};
    for (int k = 0; k < 3; ++k) i[std::size_t(k)] = int(std::lround((p[k] - f.origin[k]) / f.resolution));
    const Eigen::Vector3d node = f.origin + f.resolution * Eigen::Vector3d(i[0], i[1], i[2]);
    const double v = f.values[std::size_t(i[0]) + std::size_t(f.dims[0]) *
                                                      (std::size_t(i[1]) + std::size_t(f.dims[1]) * std::size_t(i[2]))];
    EXPECT_NEAR(v, node.x() + 1.49, 2e-3) << "at x = " << x;
    EXPECT_GT(v, previous) << "at x = " << x;
    previous = v;
  }
  EXPECT_GT(previous, 2.5) << "far beyond the old 0.25 m band";
}
