// sample_arm_motion: the viewer's frames of a result's path and retreat.
#include "dmgplace/tools/viewer/arm_motion.hpp"

#include <gtest/gtest.h>

#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "test_support.hpp"

namespace dmgplace::tools::viewer {
namespace {

// A solved result on dmgarm: a short path, then a retreat; `release` is the result's release opening.
ViewResult result(double release) {
  formats::RobotArtifact robot;
  ViewResult r;
  r.joint_names = {"dmgarm_joint1", "dmgarm_joint2", "dmgarm_joint3", "dmgarm_joint4", "dmgarm_joint5", "dmgarm_joint6",
                   "dmgarm_joint7"};
  r.start = Eigen::VectorXd(7);
  r.start << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  r.solved = true;
  r.opening = 0.04;
  r.release_opening = release;
  r.path = {r.start, r.start + Eigen::VectorXd::Constant(7, 0.1)};
  r.retreat = {r.path.back(), r.start};
  return r;
}

// The distance between the two fingers' frames at `frame`.
double finger_gap(const ArmMotion& m, const formats::RobotArtifact& robot, int frame) {
  std::vector<Eigen::Vector3d> fingers;
  for (std::size_t k = 0; k < m.links.size(); ++k) {
    const std::string& name = robot.model.links[std::size_t(m.links[k])].name;
    if (name.find("finger") == std::string::npos) continue;
    const float* p = &m.link_poses[(std::size_t(frame) * m.links.size() + k) * 7];
    fingers.emplace_back(p[0], p[1], p[2]);
  }
  EXPECT_EQ(fingers.size(), 2u);
  return fingers.size() == 2 ? (fingers[0] - fingers[1]).norm() : 0.0;
}

TEST(ArmMotion, TheRetreatOpensTheFingersAsTheResultSays) {
  formats::RobotArtifact robot;
  robot.model = read_urdf(test::source_dir() / "datasets/robots/dmgarm/dmgarm.urdf");
  robot.model.arm_base = "dmgarm_link0";
  robot.model.arm_tip = "dmgarm_tcp";
  const ArmMotion given = sample_arm_motion(result(0.06), robot, 0.08);
  const ArmMotion older = sample_arm_motion(result(0), robot, 0.08);  // no release opening: the open width
  ASSERT_GE(given.retreat_frame, 1);
  const int last = given.frames - 1;
  // Fingers are 2 x half the opening apart (plus their fixed offset): the gaps differ by 0.02.
  EXPECT_NEAR(finger_gap(older, robot, last) - finger_gap(given, robot, last), 0.02, 1e-4);
  EXPECT_NEAR(finger_gap(given, robot, last) - finger_gap(given, robot, 0), 0.02, 1e-4);  // held at 0.04
}

}  // namespace
}  // namespace dmgplace::tools::viewer
