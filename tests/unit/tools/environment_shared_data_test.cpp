// Environment analysis on real third-party data from ../shared/datasets.
#include <gtest/gtest.h>

#include <map>

#include "dmgplace/tools/environment/bake_environment.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::tools;

namespace {

formats::EnvironmentArtifact bake(const std::filesystem::path& file, const Eigen::AlignedBox3d& v,
                                  const SceneLoadOptions& load = {}) {
  formats::EnvironmentArtifact env;
  env.scene = load_scene(file, load);
  env.volume = v;
  bake_environment(env, EnvironmentBakeOptions{});
  const auto problems = formats::check_environment(env);
  EXPECT_TRUE(problems.empty()) << file << ": " << (problems.empty() ? "" : problems[0]);
  return env;
}

std::map<long, double> area_by_height(const std::vector<formats::PlacementRegion>& rs, double step = 0.001) {
  std::map<long, double> out;
  for (const auto& r : rs) out[std::lround(r.height / step)] += r.area;
  return out;
}

}  // namespace

TEST(EnvSharedData, MbmBookshelfGivesBothBoardsAroundTheCans) {
  DMGPLACE_REQUIRE_SHARED();
  const auto file = test::shared_datasets() / "env/motion_bench_maker/configs/scenes/bookshelf/scene_small.yaml";
  const auto env = bake(file, {Eigen::Vector3d(0.4, -0.48, 0.95), Eigen::Vector3d(1.6, 0.48, 1.6)});
  const auto areas = area_by_height(env.regions);
  // shelf_bottom top at 1.02 (minus three can footprints), shelf_top top at 1.32, can lids at 1.15.
  ASSERT_TRUE(areas.count(1020) && areas.count(1320) && areas.count(1150));
  EXPECT_NEAR(areas.at(1020), 1.2 * 0.96 - 3 * M_PI * 0.03 * 0.03, 0.02);
  EXPECT_NEAR(areas.at(1320), 1.2 * 0.96, 0.02);
  EXPECT_NEAR(areas.at(1150), 3 * M_PI * 0.03 * 0.03, 0.002);
  for (const auto& r : env.regions) {
    EXPECT_LE(std::max(r.width, r.depth) * r.resolution, 0.3 + 1e-9);
    for (std::size_t c = 0; c < r.mask.size(); ++c)
      if (r.mask[c]) {
        EXPECT_GE(r.free_height[c], 0.02f);
      }
  }
}

TEST(EnvSharedData, MbmKitchenBakesWithPlausibleRegions) {
  DMGPLACE_REQUIRE_SHARED();
  const auto dir = test::shared_datasets() / "env/motion_bench_maker/configs/scenes/kitchen";
  SceneLoadOptions load;
  load.urdf.package_paths.push_back(test::shared_datasets() / "env");
  const auto env = bake(dir / "kitchen.urdf", {Eigen::Vector3d(-0.5, -1.5, 0.3), Eigen::Vector3d(1.5, 1.5, 2.0)}, load);
  ASSERT_FALSE(env.regions.empty());
  double total = 0, biggest_level = 0;
  for (const auto& [h, a] : area_by_height(env.regions, 0.01)) {
    total += a;
    biggest_level = std::max(biggest_level, a);
  }
  // A kitchen counter top and cupboard shelves: square metres, not square centimetres.
  EXPECT_GT(biggest_level, 0.5);
  EXPECT_LT(total, 2.0 * 3.0 * 4);
  EXPECT_GT(*std::max_element(env.sdf.values.begin(), env.sdf.values.end()), 0.09f);
}

TEST(EnvSharedData, StereoTableScanGivesTheTableTopMinusTheMug) {
  DMGPLACE_REQUIRE_SHARED();
  // Camera frame: z forward, y down. This pose turns the table plane horizontal (fitted normal
  // (-0.057, -0.531, 0.846) in the camera frame) and puts it 0.75 m above the world floor.
  SceneLoadOptions load;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.translation() = Eigen::Vector3d(0, 0, 2.674);
  frame.linear() =
      (Eigen::AngleAxisd(-0.0571, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(2.581, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  load.frame = frame;
  const Eigen::AlignedBox3d v(Eigen::Vector3d(-0.4, -1.15, 0.6), Eigen::Vector3d(0.9, -0.6, 1.2));
  const auto env = bake(test::shared_datasets() / "scans/pcl/table_scene_mug_stereo_textured.pcd", v, load);
  EXPECT_FALSE(env.sdf_signed);
  // The table: the largest surface, at 0.75 m.
  const auto areas = area_by_height(env.regions, 0.01);
  auto best = std::max_element(areas.begin(), areas.end(), [](auto& a, auto& b) { return a.second < b.second; });
  ASSERT_NE(best, areas.end());
  EXPECT_NEAR(best->first * 0.01, 0.75, 0.011);
  EXPECT_GT(best->second, 0.2);
  // The mug (and any clutter): no table cell may have scan points 3..30 cm above it.
  int covered = 0;
  for (const auto& r : env.regions) {
    if (std::abs(r.height - 0.75) > 0.015) continue;
    for (Eigen::Index k = 0; k < env.scene.points.rows(); ++k) {
      const Eigen::Vector3d p = env.scene.points.row(k).transpose();
      if (p.z() < r.height + 0.03 || p.z() > r.height + 0.3) continue;
      const Eigen::Vector2d u = (p.head<2>() - r.origin) / r.resolution;
      const int i = int(std::floor(u.x())), j = int(std::floor(u.y()));
      if (i >= 0 && j >= 0 && i < r.width && j < r.depth &&
          r.mask[std::size_t(i) + std::size_t(r.width) * std::size_t(j)])
        ++covered;
    }
  }
  EXPECT_EQ(covered, 0);
}
