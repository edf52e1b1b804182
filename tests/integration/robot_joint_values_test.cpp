// Joints outside the arm chain set per world (a query's named start): issue 21, part 5. The
// built-in arm gets a "mast" on its base, swinging about z: at 0 it reaches into the arm's upper
// links, turned by pi/2 it stands clear.
#include <gtest/gtest.h>

#include <numbers>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/placement/placement_world.hpp"
#include "dmgplace/tools/placement/placement_query_file.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace dmgplace::test {
namespace {

const char* kMast = R"(
  <joint name="mast_joint" type="revolute">
    <parent link="dmgarm_link0"/>
    <child link="mast"/>
    <origin xyz="0 -0.3 0.45" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
  <link name="mast">
    <collision>
      <origin xyz="0 0.2 0" rpy="0 0 0"/>
      <geometry><box size="0.05 0.4 0.05"/></geometry>
    </collision>
  </link>
</robot>)";

class RobotJointValues : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    set_up_suite_or_exit("RobotJointValues", [] {
      dir_ = new TempDir();
      const auto d = dir_->path();
      const auto data = source_dir() / "datasets";
      std::string urdf = read_text(data / "robots/dmgarm/dmgarm.urdf");
      urdf.replace(urdf.rfind("</robot>"), 8, kMast);
      write_text(d / "mast.urdf", urdf);
      ASSERT_EQ(run_cli({"bake-robot", d / "mast.urdf", "--srdf", data / "robots/dmgarm/dmgarm.srdf", "--arm",
                         "dmgarm_link0:dmgarm_tcp", "--out", d / "arm.h5"})
                    .exit_code,
                0);
      ASSERT_EQ(run_cli({"make-objects", "--out", d}).exit_code, 0);
      ASSERT_EQ(run_cli({"bake-object", d / "eraser.stl", "--out", d / "eraser.h5"}).exit_code, 0);
      const std::string volume = builtin_volume("table");
      ASSERT_EQ(run_cli({"bake-env", data / "scenes/table.yaml", "--volume", volume, "--margin", "0.9",
                         "--sdf-resolution", "0.03", "--band", "0.25", "--out", d / "table.h5"})
                    .exit_code,
                0);
    });
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::unique_ptr<runtime::PlacementWorld> world(const std::map<std::string, double>& joints) {
    const auto d = dir_->path();
    return std::make_unique<runtime::PlacementWorld>(formats::load_robot(d / "arm.h5"),
                                                     formats::load_object(d / "eraser.h5"),
                                                     formats::load_environment(d / "table.h5"), -1, joints);
  }
  static Eigen::VectorXd home() {
    Eigen::VectorXd q(7);
    q << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
    return q;
  }
  static inline TempDir* dir_ = nullptr;
};

TEST_F(RobotJointValues, TheValueMovesTheLinkAndDecidesWhatCollides) {
  const auto at_zero = world({});
  const auto swung = world({{"mast_joint", std::numbers::pi / 2}});
  const auto& m = swung->kinematics().model();
  const int mast = m.link_index("mast");
  std::vector<Eigen::Isometry3d> a, b;
  at_zero->kinematics().link_poses(home(), a);
  swung->kinematics().link_poses(home(), b);
  EXPECT_NEAR((a[std::size_t(mast)].translation() - b[std::size_t(mast)].translation()).norm(), 0, 1e-12);
  const Eigen::Vector3d tip_a = a[std::size_t(mast)] * Eigen::Vector3d(0, 0.4, 0),
                        tip_b = b[std::size_t(mast)] * Eigen::Vector3d(0, 0.4, 0);
  EXPECT_NEAR((tip_a - Eigen::Vector3d(0, 0.1, 0.45)).norm(), 0, 1e-12);
  EXPECT_NEAR((tip_b - Eigen::Vector3d(-0.4, -0.3, 0.45)).norm(), 0, 1e-12);
  // The mast at 0 reaches through the upper arm; swung away it leaves the arm free.
  EXPECT_FALSE(at_zero->exact().is_free(home()));
  EXPECT_TRUE(swung->exact().is_free(home())) << swung->exact().check(home()).contact;
  // The arm chain is untouched.
  EXPECT_NEAR((at_zero->kinematics().tip_pose(home()).matrix() - swung->kinematics().tip_pose(home()).matrix()).norm(),
              0, 1e-12);
}

TEST_F(RobotJointValues, NamesThatAreNoSuchJointAreRefused) {
  const auto refused = [&](const std::map<std::string, double>& j, const std::string& why) {
    const std::string e = error_of([&] { world(j); });
    EXPECT_NE(e.find("arm.h5"), std::string::npos) << e;
    EXPECT_NE(e.find(why), std::string::npos) << e;
  };
  refused({{"elbow_of_another_arm", 1}}, "no joint of that name");
  refused({{"dmgarm_joint2", 0.1}}, "planning chain");
  refused({{"dmgarm_finger_joint1", 0.02}}, "finger");
  refused({{"dmgarm_finger_joint2", 0.02}}, "mimic");
  refused({{"dmgarm_hand_joint", 0}}, "fixed");
  refused({{"mast_joint", 2.5}}, "outside its limits");
}

TEST_F(RobotJointValues, AQueryFileNamesTheJointInItsStart) {
  const auto d = dir_->path();
  const std::string arm =
      "dmgarm_joint1: 0, dmgarm_joint2: -0.785, dmgarm_joint3: 0, dmgarm_joint4: -2.356, "
      "dmgarm_joint5: 0, dmgarm_joint6: 1.571, dmgarm_joint7: 0.785";
  write_text(d / "q.yaml", "robot: arm.h5\nobject: eraser.h5\nenvironment: table.h5\nstart: {" + arm +
                               ", mast_joint: 1.5707963}\ninitial_grasp:\n  pose: [0, 0, 0.0175, 1, 0, 0, 0]\n");
  const auto q = tools::read_placement_query(d / "q.yaml");
  const auto robot = formats::load_robot(d / "arm.h5");
  const auto joints = tools::world_joint_values(q, robot.model);
  ASSERT_EQ(joints.size(), 1u);
  EXPECT_DOUBLE_EQ(joints.at("mast_joint"), 1.5707963);
  const auto w = world(joints);
  EXPECT_TRUE(w->exact().is_free(tools::resolve_start(q, w->kinematics())));
  // A world built without it would silently plan with the mast elsewhere: refused.
  const auto plain = world({});
  const std::string e = error_of([&] { tools::resolve_start(q, plain->kinematics()); });
  EXPECT_NE(e.find("q.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("start.mast_joint"), std::string::npos) << e;
  // And through the CLI: `place` builds its world with the query's joints.
  const auto r = run_cli({"place", d / "q.yaml", "--iterations", "200", "--time-limit", "5"});
  EXPECT_NE(r.exit_code, 1) << r.output;
}

}  // namespace
}  // namespace dmgplace::test
