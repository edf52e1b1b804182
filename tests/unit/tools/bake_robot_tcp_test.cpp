// bake-robot --tcp: a TCP frame added on the tip becomes the chain's tip, where the URDF's own
// TCP link would be.
#include <gtest/gtest.h>

#include <random>

#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/robot/bake_robot.hpp"
#include "test_support.hpp"

using namespace dmgplace;

TEST(BakeRobotTcp, AddedTcpMatchesTheUrdfTcpLink) {
  const auto dir = test::source_dir() / "datasets/robots/dmgarm";
  tools::RobotBakeOptions o;
  o.urdf = dir / "dmgarm.urdf";
  o.srdf = dir / "dmgarm.srdf";
  o.arm_base = "dmgarm_link0";
  o.arm_tip = "dmgarm_tcp";
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
