// The one convention for poses people write: x y z qx qy qz qw (any non-zero length), and
// x y z roll pitch yaw (fixed axes x, y, z, as URDF) where a flag says so.
#include "dmgplace/formats/pose_input.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "test_support.hpp"

namespace dmgplace::formats {
namespace {

TEST(PoseInput, QuaternionsOfAnyLengthAreNormalisedAndZeroIsRefused) {
  const std::array<double, 7> half_turn{1, 2, 3, 0, 0, 2, 0};  // 180 deg about z, length 2
  const auto p = pose_from_xyz_quaternion(half_turn, "q.yaml", "initial_grasp.pose");
  EXPECT_TRUE(p.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE((p.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_NEAR(p.linear().determinant(), 1, 1e-12);
  const std::array<double, 7> zero{0, 0, 0, 0, 0, 0, 0};
  EXPECT_THAT(
      test::error_of([&] { pose_from_xyz_quaternion(zero, "q.yaml", "initial_grasp.pose"); }),
      ::testing::AllOf(::testing::HasSubstr("q.yaml: initial_grasp.pose"), ::testing::HasSubstr("zero quaternion")));
  const std::array<double, 7> nan{0, 0, std::nan(""), 0, 0, 0, 1};
  EXPECT_THAT(test::error_of([&] { pose_from_xyz_quaternion(nan, "--tcp", ""); }),
              ::testing::HasSubstr("not a finite number"));
}

TEST(PoseInput, RollPitchYawTurnAboutFixedAxesXThenYThenZ) {
  const double h = M_PI / 2;
  const std::array<double, 6> yaw{0, 0, 0, 0, 0, h}, roll{0, 0, 0, h, 0, 0}, both{0, 0, 0, h, 0, h};
  EXPECT_TRUE((pose_from_xyz_rpy(yaw, "--frame", "").linear() * Eigen::Vector3d::UnitX())
                  .isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE((pose_from_xyz_rpy(roll, "--frame", "").linear() * Eigen::Vector3d::UnitY())
                  .isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  // Roll first (y -> z), then yaw about the fixed z (z stays): y ends on z.
  EXPECT_TRUE((pose_from_xyz_rpy(both, "--frame", "").linear() * Eigen::Vector3d::UnitY())
                  .isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

}  // namespace
}  // namespace dmgplace::formats
