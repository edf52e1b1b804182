// bake-robot --tcp: a TCP frame added on the tip becomes the chain's tip, where the URDF's own
// TCP link would be.
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/robot/bake_robot.hpp"
#include "test_support.hpp"

using namespace dmgplace;

namespace {
// The built-in dmgarm with its SRDF, chain base to TCP.
tools::RobotBakeOptions dmgarm_options() {
  const auto dir = test::source_dir() / "datasets/robots/dmgarm";
  tools::RobotBakeOptions o;
  o.urdf = dir / "dmgarm.urdf";
  o.srdf = dir / "dmgarm.srdf";
  o.arm_base = "dmgarm_link0";
  o.arm_tip = "dmgarm_tcp";
  return o;
}
}  // namespace

TEST(BakeRobotTcp, AddedTcpMatchesTheUrdfTcpLink) {
  tools::RobotBakeOptions o = dmgarm_options();
  const auto reference = tools::bake_robot(o);
  o.arm_tip = "dmgarm_hand";
  o.tcp = Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.1034));
  const auto added = tools::bake_robot(o);
  EXPECT_EQ(added.model.arm_tip, "dmgarm_hand_tcp");
  const runtime::Kinematics a(reference.model, "dmgarm_link0", "dmgarm_tcp");
  const runtime::Kinematics b(added.model, "dmgarm_link0", "dmgarm_hand_tcp");
  ASSERT_EQ(a.dof(), b.dof());
  std::mt19937_64 rng(3);
  for (int k = 0; k < 100; ++k) {
    Eigen::VectorXd q(a.dof());
    for (int i = 0; i < a.dof(); ++i) q[i] = std::uniform_real_distribution<double>(a.lower()[i], a.upper()[i])(rng);
    EXPECT_TRUE(a.tip_pose(q).isApprox(b.tip_pose(q), 1e-9));
  }
  o.arm_tip = "no_such_link";
  EXPECT_NE(test::error_of([&] { tools::bake_robot(o); }).find("no_such_link"), std::string::npos);
}

// bake-robot --fixed-joints: a joint outside the chain is frozen at the value given (its mimic
// followers too); chain joints, unknown names and values beyond the limits are refused.
TEST(BakeRobotFixedJoints, FreezesJointsOutsideTheChainWhereAsked) {
  tools::RobotBakeOptions o = dmgarm_options();
  o.self_tables.enabled = false;
  const auto free = tools::bake_robot(o);
  o.fixed_joints = {{"dmgarm_finger_joint1", 0.03}};
  const auto frozen = tools::bake_robot(o);
  const auto& m = frozen.model;
  const int j1 = m.joint_index("dmgarm_finger_joint1"), j2 = m.joint_index("dmgarm_finger_joint2");
  EXPECT_EQ(m.joints[std::size_t(j1)].type, JointType::Fixed);
  EXPECT_EQ(m.joints[std::size_t(j2)].type, JointType::Fixed) << "its mimic follows";
  // The fingers stand 2 x 0.03 apart, whatever the kinematics' own finger values.
  const runtime::Kinematics kin(m, m.arm_base, m.arm_tip), kin_free(free.model, m.arm_base, m.arm_tip);
  std::vector<Eigen::Isometry3d> poses;
  kin.link_poses(Eigen::VectorXd::Zero(kin.dof()), poses);
  const int left = m.link_index("dmgarm_leftfinger"), right = m.link_index("dmgarm_rightfinger");
  EXPECT_NEAR((poses[std::size_t(left)].translation() - poses[std::size_t(right)].translation()).norm(), 0.06, 1e-9);
  EXPECT_EQ(kin.dof(), kin_free.dof());
  o.fixed_joints = {{"dmgarm_joint2", 0.1}};
  EXPECT_NE(test::error_of([&] { tools::bake_robot(o); }).find("planning chain"), std::string::npos);
  o.fixed_joints = {{"no_joint", 0.1}};
  EXPECT_NE(test::error_of([&] { tools::bake_robot(o); }).find("no joint named 'no_joint'"), std::string::npos);
  o.fixed_joints = {{"dmgarm_finger_joint1", 0.5}};
  EXPECT_NE(test::error_of([&] { tools::bake_robot(o); }).find("outside its limits"), std::string::npos);
  o.fixed_joints = {{"dmgarm_finger_joint2", 0.01}};
  EXPECT_NE(test::error_of([&] { tools::bake_robot(o); }).find("mimic"), std::string::npos);
}
