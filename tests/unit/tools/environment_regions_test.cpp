// Placement regions from geometry and from scans.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "analytic_sdf.hpp"
#include "dmgplace/tools/environment/bake_environment.hpp"
#include "dmgplace/tools/environment/geometry_regions.hpp"
#include "dmgplace/tools/environment/scan_regions.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::tools;
using formats::PlacementRegion;

namespace {

Shape box(const Eigen::Vector3d& size, const Eigen::Vector3d& at) { return test::box_shape(size, at); }

std::vector<PlacementRegion> geometry_regions(const Scene& scene, const Eigen::AlignedBox3d& v, RegionOptions o) {
  const EnvironmentGeometry geo = make_environment_geometry(scene);
  const EmbreeScene embree(geo);
  const CellGrid grid = cell_grid(v, o.resolution);
  return build_regions(grid, geometry_surface_samples(embree, v, grid, o), o);
}

// Total area per surface height (mm-rounded), summed over split siblings.
std::map<long, double> area_by_height(const std::vector<PlacementRegion>& rs) {
  std::map<long, double> out;
  for (const auto& r : rs) out[std::lround(r.height * 1000)] += r.area;
  return out;
}

bool cell_in(const PlacementRegion& r, const Eigen::Vector2d& xy) {
  const Eigen::Vector2d u = (xy - r.origin) / r.resolution;
  const int i = int(std::floor(u.x())), j = int(std::floor(u.y()));
  return i >= 0 && j >= 0 && i < r.width && j < r.depth &&
         r.mask[std::size_t(i) + std::size_t(r.width) * std::size_t(j)];
}

}  // namespace

TEST(EnvRegions, BoxOnAFloorGivesItsTopAndTheFloorMinusItsFootprint) {
  Scene scene;
  scene.objects.push_back({"floor", {box({2, 2, 0.02}, {0, 0, -0.01})}});
  scene.objects.push_back({"box", {box({0.2, 0.1, 0.15}, {0.1, 0.05, 0.075})}});
  const Eigen::AlignedBox3d v(Eigen::Vector3d(-0.3, -0.3, -0.05), Eigen::Vector3d(0.3, 0.3, 0.5));
  RegionOptions o;
  o.split_size = 10;  // no splitting here
  const auto rs = geometry_regions(scene, v, o);
  ASSERT_EQ(rs.size(), 2u);
  const PlacementRegion& floor = rs[0].height < rs[1].height ? rs[0] : rs[1];
  const PlacementRegion& top = rs[0].height < rs[1].height ? rs[1] : rs[0];
  EXPECT_NEAR(floor.height, 0.0, 1e-9);
  EXPECT_NEAR(top.height, 0.15, 1e-9);
  // 60 x 60 cells minus the 20 x 10 footprint; the top is the box's 20 x 10 cells.
  EXPECT_NEAR(floor.area, 0.36 - 0.02, 1e-9);
  EXPECT_NEAR(top.area, 0.02, 1e-9);
  EXPECT_FALSE(cell_in(floor, {0.1, 0.05}));
  EXPECT_TRUE(cell_in(floor, {-0.2, -0.2}));
  EXPECT_TRUE(cell_in(top, {0.1, 0.05}));
  // Free height: up to the top of V on the floor, 0.5 - 0.15 on the box.
  for (std::size_t c = 0; c < top.mask.size(); ++c)
    if (top.mask[c]) {
      EXPECT_NEAR(top.free_height[c], 0.35, 1e-6);
    }
}

TEST(EnvRegions, AShelfGivesOneRegionPerBoard) {
  Scene scene;
  scene.objects.push_back({"side_l", {box({0.3, 0.02, 1.0}, {0, -0.26, 0.5})}});
  scene.objects.push_back({"side_r", {box({0.3, 0.02, 1.0}, {0, 0.26, 0.5})}});
  for (double z : {0.1, 0.4, 0.7}) scene.objects.push_back({"board", {box({0.3, 0.5, 0.02}, {0, 0, z - 0.01})}});
  scene.objects.push_back({"top", {box({0.3, 0.54, 0.02}, {0, 0, 1.01})}});
  const Eigen::AlignedBox3d v(Eigen::Vector3d(-0.15, -0.25, 0.05), Eigen::Vector3d(0.15, 0.25, 1.0));
  const auto rs = geometry_regions(scene, v, RegionOptions{});
  const auto by_height = area_by_height(rs);
  ASSERT_EQ(by_height.size(), 3u);
  for (long h : {100L, 400L, 700L}) EXPECT_NEAR(by_height.at(h), 0.3 * 0.5, 1e-9) << h;
  std::map<long, std::set<int>> surfaces;
  for (const auto& r : rs) surfaces[std::lround(r.height * 1000)].insert(r.surface);
  for (const auto& [h, s] : surfaces) EXPECT_EQ(s.size(), 1u) << "board " << h << " is one surface";
  // Under the next board: 0.3 m minus its 0.02 thickness.
  for (const auto& r : rs)
    if (std::lround(r.height * 1000) == 100)
      for (std::size_t c = 0; c < r.mask.size(); ++c)
        if (r.mask[c]) {
          EXPECT_NEAR(r.free_height[c], 0.28, 1e-6);
        }
}

TEST(EnvRegions, LargeSurfacesAreSplitIntoBalancedPiecesNoLongerThanTheLimit) {
  Scene scene;
  scene.objects.push_back({"table", {box({1.0, 0.4, 0.02}, {0.5, 0.2, -0.01})}});
  const Eigen::AlignedBox3d v(Eigen::Vector3d(0, 0, -0.05), Eigen::Vector3d(1, 0.4, 0.5));
  const auto rs = geometry_regions(scene, v, RegionOptions{});
  ASSERT_GE(rs.size(), 4u);
  double total = 0, smallest = 1, largest = 0;
  for (const auto& r : rs) {
    EXPECT_LE(r.width * r.resolution, 0.3 + 1e-9);
    EXPECT_LE(r.depth * r.resolution, 0.3 + 1e-9);
    EXPECT_EQ(r.surface, rs[0].surface);
    total += r.area;
    smallest = std::min(smallest, r.area);
    largest = std::max(largest, r.area);
  }
  EXPECT_NEAR(total, 0.4, 1e-9);
  EXPECT_LE(largest, 2.2 * smallest) << "median splits keep siblings of similar size";
}

TEST(EnvRegions, AScanOfAPlaneGivesOneRegionAtItsHeightMinusClutter) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.002);
  std::vector<Eigen::Vector3d> pts;
  // A can (r = 3 cm, 8 cm tall) stands at (0.12, 0.12): the scanner sees its wall and lid, not
  // the plane under it.
  const Eigen::Vector2d can(0.12, 0.12);
  for (double x = 0.0; x <= 0.25; x += 0.003)
    for (double y = 0.0; y <= 0.25; y += 0.003)
      if ((Eigen::Vector2d(x, y) - can).norm() > 0.03) pts.emplace_back(x, y, 0.3 + noise(rng));
  for (double a = 0; a < 2 * M_PI; a += 0.05)
    for (double z = 0.302; z <= 0.38; z += 0.004)
      pts.emplace_back(can.x() + 0.03 * std::cos(a), can.y() + 0.03 * std::sin(a), z);
  for (double x = -0.03; x <= 0.03; x += 0.004)
    for (double y = -0.03; y <= 0.03; y += 0.004)
      if (std::hypot(x, y) < 0.03) pts.emplace_back(can.x() + x, can.y() + y, 0.38);
  RowMatrixX3d m(Eigen::Index(pts.size()), 3);
  for (std::size_t i = 0; i < pts.size(); ++i) m.row(Eigen::Index(i)) = pts[i].transpose();
  const Eigen::AlignedBox3d v(Eigen::Vector3d(-0.05, -0.05, 0.2), Eigen::Vector3d(0.3, 0.3, 0.7));
  RegionOptions o;
  const CellGrid grid = cell_grid(v, o.resolution);
  const auto rs = build_regions(grid, scan_surface_samples(m, v, grid, o), o);
  ASSERT_EQ(rs.size(), 1u);
  EXPECT_NEAR(rs[0].height, 0.3, 0.003);
  EXPECT_NEAR(rs[0].area, 0.25 * 0.25 - M_PI * 0.03 * 0.03, 0.012);
  EXPECT_FALSE(cell_in(rs[0], {0.12 + 0.03, 0.12}));  // under the can's wall
  EXPECT_FALSE(cell_in(rs[0], can));
  EXPECT_TRUE(cell_in(rs[0], {0.05, 0.2}));
}

TEST(EnvRegions, BuiltInCabinetHasARegionPerShelfAndTableTopMinusClutter) {
  const auto data = test::source_dir() / "datasets/scenes";
  auto bake = [&](const std::string& name, const Eigen::AlignedBox3d& v) {
    formats::EnvironmentArtifact env;
    env.scene = read_planning_scene_yaml(data / (name + ".yaml"));
    env.volume = v;
    bake_environment(env, EnvironmentBakeOptions{});
    EXPECT_TRUE(formats::check_environment(env).empty()) << name;
    return env;
  };
  const auto cabinet = bake("cabinet", {Eigen::Vector3d(0.55, -0.40, 0.45), Eigen::Vector3d(0.88, 0.40, 1.04)});
  const auto shelves = area_by_height(cabinet.regions);
  // Shelf 1 (z 0.45) and shelf 2 (z 0.75) are large; clutter tops are small.
  ASSERT_TRUE(shelves.count(450) && shelves.count(750));
  EXPECT_GT(shelves.at(450), 0.15);
  EXPECT_GT(shelves.at(750), 0.2);
  for (const auto& [h, area] : shelves)
    if (h != 450 && h != 750) {
      EXPECT_LT(area, 0.02) << "only clutter tops besides the shelves, got " << h;
    }

  const auto table = bake("table", {Eigen::Vector3d(0.25, -0.60, 0.41), Eigen::Vector3d(1.00, 0.60, 0.80)});
  Scene clutter = table.scene;
  std::erase_if(clutter.objects,
                [](const SceneObject& o) { return o.name == "floor" || o.name.rfind("table", 0) == 0; });
  double top_area = 0;
  int inside_clutter = 0;
  for (const auto& r : table.regions) {
    if (std::lround(r.height * 1000) != 420) continue;
    top_area += r.area;
    for (int j = 0; j < r.depth; ++j)
      for (int i = 0; i < r.width; ++i)
        if (r.mask[std::size_t(i) + std::size_t(r.width) * std::size_t(j)]) {
          const Eigen::Vector2d c = r.cell_center(i, j);
          inside_clutter += test::scene_signed_distance(clutter, Eigen::Vector3d(c.x(), c.y(), 0.425)) < 0;
        }
  }
  EXPECT_EQ(inside_clutter, 0) << "table-top cells under clutter";
  // The table inside V is 0.75 x 1.2 m; clutter footprints take roughly 0.1 m^2.
  EXPECT_GT(top_area, 0.75 * 1.2 - 0.13);
  EXPECT_LT(top_area, 0.75 * 1.2 - 0.06);
}
