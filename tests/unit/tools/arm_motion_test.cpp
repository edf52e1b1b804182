// sample_arm_motion: the viewer's frames of a result's path and retreat.
#include "dmgplace/tools/viewer/arm_motion.hpp"

#include <gtest/gtest.h>

#include "dmgplace/runtime/motion/trajectory.hpp"
#include "dmgplace/runtime/placement/push_geometry.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"
#include "test_support.hpp"

namespace dmgplace::tools::viewer {
namespace {

// A solved result on dmgarm: a short path, then a retreat; `release` is the result's release opening.
ViewResult result(double release) {
  formats::RobotArtifact robot;
  ViewResult r;
  r.joint_names = {"dmgarm_joint1", "dmgarm_joint2", "dmgarm_joint3", "dmgarm_joint4",
                   "dmgarm_joint5", "dmgarm_joint6", "dmgarm_joint7"};
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

formats::RobotArtifact robot_artifact(const std::string& name, const std::string& tip) {
  formats::RobotArtifact robot;
  robot.model = read_urdf(test::source_dir() / ("datasets/robots/" + name + "/" + name + ".urdf"));
  robot.model.arm_base = "dmgarm_link0";
  robot.model.arm_tip = tip;
  return robot;
}

runtime::Trajectory timed(const std::vector<Eigen::VectorXd>& path, double velocity) {
  runtime::JointPath p;
  for (const auto& q : path) p.emplace_back(q.data(), q.data() + q.size());
  const std::size_t n = std::size_t(path.front().size());
  return runtime::time_parameterize(p, {std::vector<double>(n, velocity), std::vector<double>(n, 2 * velocity)});
}

Eigen::Isometry3d pose_at(const std::vector<float>& poses, std::size_t k) {
  const float* p = &poses[k * 7];
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(p[6], p[3], p[4], p[5]).normalized().toRotationMatrix();
  t.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  return t;
}

double pose_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm() + Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

// Interpolates a trajectory's positions at time t, as an independent reference.
Eigen::VectorXd reference_at(const runtime::Trajectory& tr, double t) {
  std::size_t i = 1;
  while (i + 1 < tr.time.size() && tr.time[i] < t) ++i;
  const double w = std::clamp((t - tr.time[i - 1]) / (tr.time[i] - tr.time[i - 1]), 0.0, 1.0);
  const Eigen::Map<const Eigen::VectorXd> a(tr.positions[i - 1].data(), Eigen::Index(tr.positions[i - 1].size()));
  const Eigen::Map<const Eigen::VectorXd> b(tr.positions[i].data(), Eigen::Index(tr.positions[i].size()));
  return a + w * (b - a);
}

TEST(ArmMotion, FramesFollowTheTimedTrajectoriesInRealTime) {
  const formats::RobotArtifact robot = robot_artifact("dmgarm", "dmgarm_tcp");
  for (double velocity : {0.5, 2.0}) {
    ViewResult r = result(0.06);
    r.path.insert(r.path.begin() + 1, r.start + Eigen::VectorXd::Constant(7, -0.2));
    r.path_timing = timed(r.path, velocity);
    r.retreat_timing = timed(r.retreat, velocity);
    const double period = 0.05;
    const ArmMotion m = sample_arm_motion(r, robot, 0.08, period);
    ASSERT_EQ(m.frame_times.size(), std::size_t(m.frames));
    EXPECT_EQ(m.frame_times.front(), 0.0f);
    EXPECT_NEAR(m.frame_times.back(), r.path_timing.duration() + r.retreat_timing.duration(), 1e-5);
    for (int k = 1; k < m.frames; ++k) {
      EXPECT_GE(m.frame_times[std::size_t(k)], m.frame_times[std::size_t(k - 1)]);
      EXPECT_LE(m.frame_times[std::size_t(k)] - m.frame_times[std::size_t(k - 1)], period + 1e-5);
    }
    // Each frame shows the trajectory at the frame's time: the tip where FK puts it.
    runtime::Kinematics kin(robot.model, "dmgarm_link0", "dmgarm_tcp");
    std::size_t tip = 0;
    while (robot.model.links[std::size_t(m.links[tip])].name != "dmgarm_hand") ++tip;
    std::vector<Eigen::Isometry3d> poses;
    for (int k = 0; k < m.frames; ++k) {
      const double t = m.frame_times[std::size_t(k)];
      const bool retreating = k >= m.retreat_frame;
      const runtime::Trajectory& tr = retreating ? r.retreat_timing : r.path_timing;
      kin.link_poses(reference_at(tr, retreating ? t - r.path_timing.duration() : t), poses);
      const int hand = m.links[tip];
      EXPECT_LT(pose_error(pose_at(m.link_poses, std::size_t(k) * m.links.size() + tip), poses[std::size_t(hand)]),
                1e-4)
          << "frame " << k << " at " << t << " s";
    }
    // Waypoint frames in order, the path's last at the release.
    ASSERT_EQ(m.waypoint_frames.size(), r.path.size() + r.retreat.size());
    EXPECT_TRUE(std::is_sorted(m.waypoint_frames.begin(), m.waypoint_frames.end()));
    EXPECT_EQ(m.waypoint_frames[r.path.size() - 1], m.retreat_frame - 1);
    EXPECT_EQ(m.waypoint_frames.back(), m.frames - 1);
  }
}

TEST(ArmMotion, AResultWithoutTimingPlaysAtANominalSpeed) {
  const formats::RobotArtifact robot = robot_artifact("dmgarm", "dmgarm_tcp");
  const ViewResult r = result(0.06);
  const ArmMotion m = sample_arm_motion(r, robot, 0.08);
  const double expected = 0.2 / 1.2;  // two segments of 0.1 rad on the fastest joint at 1.2 rad/s
  EXPECT_NEAR(m.frame_times.back(), expected, 1e-5);
  EXPECT_EQ(m.waypoint_frames.size(), 4u);
}

TEST(ArmMotion, PushesPlayFirstAndCarryTheObjectWhileInContact) {
  const formats::RobotArtifact robot = robot_artifact("dmgdual", "dmgarm_tcp");
  ViewResult r = result(0.06);
  r.joint_values = {{"pusher_joint1", 2.9}};
  r.pusher_tip = "pusher_tcp";
  runtime::Kinematics pusher(robot.model, "dmgarm_link0", "pusher_tcp");
  r.pusher_joint_names = pusher.joint_names();
  ASSERT_EQ(r.pusher_joint_names.size(), 7u);
  const runtime::Kinematics arm(robot.model, "dmgarm_link0", "dmgarm_tcp");
  const Eigen::Isometry3d tcp = arm.tip_pose(r.start);
  ViewResult::Push p;
  Eigen::VectorXd park(7);
  park << 2.9, -0.785, 0, -2.356, 0, 1.571, 0.785;
  p.path = {park, park + Eigen::VectorXd::Constant(7, 0.2), park + Eigen::VectorXd::Constant(7, 0.3), park};
  p.begin = 1;
  p.end = 2;
  // Timed by hand: a waypoint a second, so the contact runs from 1 s to 2 s.
  for (std::size_t i = 0; i < p.path.size(); ++i) {
    p.timing.time.push_back(double(i));
    p.timing.positions.emplace_back(p.path[i].data(), p.path[i].data() + 7);
  }
  // The object turns 30 degrees about the finger axis (the TCP's y) in the still hand.
  p.object_before = tcp * Eigen::Translation3d(0, 0, 0.05);
  p.object_after = tcp * Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitY()) * tcp.inverse() * p.object_before;
  r.pushes = {p};
  const ArmMotion m = sample_arm_motion(r, robot, 0.08, 0.02);
  ASSERT_EQ(m.push_frames, std::vector<int>{0});
  const int path_first = m.waypoint_frames.front();
  EXPECT_NEAR(m.frame_times[std::size_t(path_first)], p.timing.duration(), 1e-5);
  std::size_t tool = 0;
  while (robot.model.links[std::size_t(m.links[tool])].name != "pusher_link7") ++tool;
  std::vector<Eigen::Isometry3d> poses;
  const double begin = 1, end = 2;
  const runtime::ObjectMotion motion =
      runtime::object_motion(tcp, p.object_before.inverse() * tcp, p.object_after.inverse() * tcp);
  for (int k = 0; k < path_first; ++k) {
    const double t = m.frame_times[std::size_t(k)];
    pusher.link_poses(reference_at(p.timing, t), poses);
    EXPECT_LT(
        pose_error(pose_at(m.link_poses, std::size_t(k) * m.links.size() + tool), poses[std::size_t(m.links[tool])]),
        1e-4)
        << "frame " << k;
    const double s = std::clamp((t - begin) / (end - begin), 0.0, 1.0);
    EXPECT_LT(pose_error(pose_at(m.object_poses, std::size_t(k)), motion.at(s) * p.object_before), 1e-4)
        << "frame " << k;
  }
  EXPECT_LT(pose_error(pose_at(m.object_poses, std::size_t(path_first - 1)), p.object_after), 1e-4);
}

}  // namespace
}  // namespace dmgplace::tools::viewer
