// apply_joint_limits: MoveIt's joint_limits.yaml over a model.
#include "dmgplace/tools/io/joint_limits_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

using ::testing::HasSubstr;

RobotModel two_joints() {
  RobotModel m;
  for (auto n : {"base", "a", "b"}) m.links.push_back({n, {}});
  Joint j;
  j.name = "shoulder";
  j.type = JointType::Revolute;
  j.parent = 0;
  j.child = 1;
  j.lower = -2;
  j.upper = 2;
  j.velocity = 3;
  Joint k = j;
  k.name = "elbow";
  k.parent = 1;
  k.child = 2;
  k.velocity = 0;
  m.joints = {j, k};
  return m;
}

RobotModel applied(const std::string& yaml, JointLimitsFile* read = nullptr) {
  test::TempDir dir;
  test::write_text(dir / "joint_limits.yaml", yaml);
  RobotModel m = two_joints();
  const JointLimitsFile r = apply_joint_limits(m, dir / "joint_limits.yaml");
  if (read) *read = r;
  return m;
}

std::string refusal(const std::string& yaml) {
  return test::error_of([&] { applied(yaml); });
}

TEST(JointLimitsFile, OverridesWhatItGivesAndKeepsTheRest) {
  JointLimitsFile read;
  const RobotModel m = applied(R"(default_velocity_scaling_factor: 0.1
joint_limits:
  shoulder:
    has_velocity_limits: true
    max_velocity: 1.5
    has_acceleration_limits: true
    max_acceleration: 4.0
    has_position_limits: true
    min_position: -1
    max_position: 1.5
  elbow:
    has_velocity_limits: false
    max_velocity: 9
    has_acceleration_limits: true
    max_acceleration: 2
    has_jerk_limits: false
)",
                               &read);
  EXPECT_DOUBLE_EQ(m.joints[0].velocity, 1.5);
  EXPECT_DOUBLE_EQ(m.joints[0].acceleration, 4.0);
  EXPECT_DOUBLE_EQ(m.joints[0].lower, -1);
  EXPECT_DOUBLE_EQ(m.joints[0].upper, 1.5);
  EXPECT_DOUBLE_EQ(m.joints[1].velocity, 0);  // has_velocity_limits: false keeps the URDF's
  EXPECT_DOUBLE_EQ(m.joints[1].acceleration, 2);
  ASSERT_EQ(read.notes.size(), 1u);  // the scaling default is read and said to be unused
  EXPECT_THAT(read.notes[0], HasSubstr("default_velocity_scaling_factor"));
}

TEST(JointLimitsFile, RefusesWhatItCannotUse) {
  EXPECT_THAT(refusal("joint_limits:\n  wrist: {has_velocity_limits: true, max_velocity: 1}\n"),
              HasSubstr("joint_limits.wrist: no joint 'wrist'"));
  EXPECT_THAT(refusal("joint_limits:\n  shoulder: {has_acceleration_limits: true, max_acceleration: 0}\n"),
              HasSubstr("max_acceleration: must be finite and > 0"));
  EXPECT_THAT(refusal("joint_limits:\n  shoulder: {has_acceleration_limits: true, max_acceleration: .nan}\n"),
              HasSubstr("must be finite and > 0"));
  EXPECT_THAT(refusal("joint_limits:\n  shoulder: {has_acceleration_limits: true}\n"),
              HasSubstr("max_acceleration is missing"));
  EXPECT_THAT(refusal("joint_limits:\n  shoulder: {has_velocity_limit: true, max_velocity: 1}\n"),
              HasSubstr("has_velocity_limit"));
  EXPECT_THAT(refusal("joint_limits:\n  shoulder: {has_position_limits: true, min_position: -3, max_position: 1}\n"),
              HasSubstr("wider than the URDF"));
  EXPECT_THAT(refusal("joint_limits:\n  shoulder: {has_velocity_limits: maybe, max_velocity: 1}\n"),
              HasSubstr("expected true or false"));
  EXPECT_THAT(refusal("limits: {}\n"), HasSubstr("limits"));
  EXPECT_THAT(refusal("joint_limits: [1, 2]\n"), HasSubstr("expected a map"));
}

}  // namespace
}  // namespace dmgplace::tools
