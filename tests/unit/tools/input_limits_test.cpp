// Issue 19, item 4: limits that were not enforced. Each input here once hung, ran out of memory or
// "finished" at once; now each is refused up front with the file, the element and the limit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/placement/placement_planner.hpp"
#include "dmgplace/tools/io/scene_loader.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string box_scene(const std::string& dimensions, int copies = 1) {
  std::string s = "world:\n  collision_objects:\n";
  for (int i = 0; i < copies; ++i)
    s += "    - id: box" + std::to_string(i) +
         "\n      primitives:\n        - type: box\n          dimensions: " + dimensions +
         "\n      primitive_poses:\n        - position: [0, 0, 0]\n          orientation: [0, 0, 0, 1]\n";
  return s;
}

TEST(InputLimits, ScenesBeyondAKilometreAreRefused) {
  test::TempDir dir;
  test::write_text(dir / "ok.yaml", box_scene("[1, 1, 1]"));
  EXPECT_EQ(load_scene(dir / "ok.yaml").objects.size(), 1u);
  test::write_text(dir / "far.yaml", box_scene("[1e300, 1, 1]"));
  EXPECT_THAT(test::error_of([&] { load_scene(dir / "far.yaml"); }),
              AllOf(HasSubstr((dir / "far.yaml").string()), HasSubstr("object 'box0'"), HasSubstr("beyond 1000 m")));
}

TEST(InputLimits, SceneObjectCountIsBounded) {
  test::TempDir dir;
  test::write_text(dir / "many.yaml", box_scene("[0.1, 0.1, 0.1]", 10001));
  EXPECT_THAT(test::error_of([&] { load_scene(dir / "many.yaml"); }),
              AllOf(HasSubstr((dir / "many.yaml").string()), HasSubstr("10001 objects"),
                    HasSubstr("more than this build handles")));
}

// A 900 m link at the default 5 mm spacing would need ~10^16 samples: refused before sampling.
TEST(InputLimits, SphereCoverCountsItsSamplesBeforeMakingThem) {
  Shape box;
  box.type = ShapeType::Box;
  box.size = Eigen::Vector3d(900, 1, 1);
  EXPECT_THAT(test::error_of([&] { cover_with_spheres({box}); }),
              AllOf(HasSubstr("samples"), HasSubstr("--sphere-spacing")));
  // A small box still gets its cover.
  box.size = Eigen::Vector3d(0.1, 0.1, 0.1);
  EXPECT_FALSE(cover_with_spheres({box}).empty());
}

// 1e12 s in nanoseconds overflows a 64-bit count: the deadline wrapped into the past and the
// query "finished" at once.
TEST(InputLimits, HugeTimeLimitsDoNotWrapIntoThePast) {
  const auto stop = runtime::stop_after_seconds(1e12);
  EXPECT_FALSE(stop());
  EXPECT_FALSE(runtime::stop_after_seconds(1e300)());
  EXPECT_TRUE(runtime::stop_after_seconds(0)());
  EXPECT_TRUE(runtime::stop_after_seconds(std::nan(""))());
}

}  // namespace
}  // namespace dmgplace::tools
