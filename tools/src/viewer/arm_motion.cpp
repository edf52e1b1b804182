#include "dmgplace/tools/viewer/arm_motion.hpp"

#include <algorithm>
#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/placement/push_geometry.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::tools::viewer {
namespace {

void push_pose(std::vector<float>& out, const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.rotation());
  for (double v : {t.translation().x(), t.translation().y(), t.translation().z(), q.x(), q.y(), q.z(), q.w()})
    out.push_back(float(v));
}

bool below(const RobotModel& m, int link, int ancestor) {
  for (int guard = 0; link >= 0 && guard <= int(m.links.size()); ++guard) {
    if (link == ancestor) return true;
    auto it = std::find_if(m.joints.begin(), m.joints.end(), [&](const Joint& j) { return j.child == link; });
    link = it == m.joints.end() ? -1 : it->parent;
  }
  return false;
}

// The topmost link fixed to `link`: the hand that carries the TCP frame (and the fingers).
int rigid_root(const RobotModel& m, int link) {
  for (int guard = 0; guard <= int(m.links.size()); ++guard) {
    auto it = std::find_if(m.joints.begin(), m.joints.end(), [&](const Joint& j) { return j.child == link; });
    if (it == m.joints.end() || it->type != JointType::Fixed) return link;
    link = it->parent;
  }
  return link;
}

// Finger joints: movable, outside the chain, not mimicking, on the hand that carries the tip (as
// PlacementWorld does: the TCP is often a leaf beside the fingers, not above them).
std::vector<const Joint*> finger_joints(const runtime::Kinematics& kin) {
  const auto& m = kin.model();
  const int hand = rigid_root(m, kin.tip_link());
  std::vector<const Joint*> out;
  for (const auto& j : m.joints) {
    const auto& names = kin.joint_names();
    if (j.type == JointType::Fixed || j.mimic >= 0 || std::find(names.begin(), names.end(), j.name) != names.end())
      continue;
    if (below(m, j.child, hand)) out.push_back(&j);
  }
  return out;
}

// Where a result has no timing (older results), its paths play at this speed of the fastest joint.
constexpr double kNominalSpeed = 1.2;  // rad/s

// One phase of the motion: configurations over time from the phase's start.
struct Timed {
  std::vector<double> time;
  std::vector<Eigen::VectorXd> q;
  double duration() const { return time.empty() ? 0.0 : time.back(); }
  Eigen::VectorXd at(double t) const {
    const auto hi = std::upper_bound(time.begin(), time.end(), t);
    if (hi == time.begin()) return q.front();
    if (hi == time.end()) return q.back();
    const std::size_t i = std::size_t(hi - time.begin());
    const double w = (t - time[i - 1]) / (time[i] - time[i - 1]);
    return q[i - 1] + w * (q[i] - q[i - 1]);
  }
};

// The result's timed trajectory of `path` where it has one, else the path at kNominalSpeed.
Timed timed(const std::vector<Eigen::VectorXd>& path, const runtime::Trajectory& trajectory) {
  Timed out;
  if (!trajectory.empty()) {
    out.time = trajectory.time;
    for (const auto& q : trajectory.positions)
      out.q.push_back(Eigen::Map<const Eigen::VectorXd>(q.data(), Eigen::Index(q.size())));
    return out;
  }
  double t = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) t += (path[i] - path[i - 1]).cwiseAbs().maxCoeff() / kNominalSpeed;
    out.time.push_back(t);
    out.q.push_back(path[i]);
  }
  return out;
}

// When the timed motion passes each waypoint of the path it follows: the first local minimum of
// the distance to it, searched on from the previous waypoint's (the trajectory blends corners, so
// it passes near a waypoint rather than through it). The first is at 0, the last at the end.
std::vector<double> waypoint_times(const Timed& m, const std::vector<Eigen::VectorXd>& path) {
  std::vector<double> out;
  std::size_t k = 0;
  for (std::size_t w = 0; w < path.size(); ++w) {
    if (w + 1 == path.size()) k = m.q.size() - 1;
    double best = (m.q[k] - path[w]).norm();
    for (std::size_t i = k + 1; i < m.q.size(); ++i) {
      const double d = (m.q[i] - path[w]).norm();
      if (d > best + 1e-9) break;
      if (d <= best) best = d, k = i;
    }
    out.push_back(w == 0 ? 0.0 : m.time[k]);
  }
  return out;
}

// Calls frame(local time) at 0, period, 2 period, ... and at the phase's end; returns the frame
// count. A phase of no duration gets one frame.
template <class Frame>
int sample_phase(double duration, double period, Frame&& frame) {
  int n = 0;
  for (double t = 0; t < duration - 1e-9; t = ++n * period) frame(t);
  frame(duration);
  return n + 1;
}
}  // namespace

ArmMotion sample_arm_motion(const ViewResult& r, const formats::RobotArtifact& robot, double open_width,
                            double frame_period, int max_frames) {
  runtime::Kinematics kin(robot.model, robot.model.arm_base, robot.model.arm_tip);
  if (kin.joint_names() != r.joint_names)
    throw Error(
        r.file.string(), "/joint_names",
        "not the arm chain of " + r.robot.string() + " (" + robot.model.arm_base + " -> " + robot.model.arm_tip + ")");
  const auto fingers = finger_joints(kin);
  for (const auto& [name, value] : r.joint_values) kin.set_joint_value(name, value);
  ArmMotion m;
  for (std::size_t l = 0; l < robot.model.links.size(); ++l)
    if (!robot.model.links[l].collision.empty()) m.links.push_back(int(l));

  std::vector<Eigen::Isometry3d> poses;
  double offset = 0;  // the current phase's start, s
  const auto add_frame = [&](double at, const std::vector<Eigen::Isometry3d>& links, const Eigen::Isometry3d& object) {
    for (int l : m.links) push_pose(m.link_poses, links[std::size_t(l)]);
    push_pose(m.object_poses, object);
    m.frame_times.push_back(float(offset + at));
    ++m.frames;
  };
  const auto arm_frame = [&](double at, const Eigen::VectorXd& q, double opening,
                             const Eigen::Isometry3d* object_rest) {
    for (const Joint* j : fingers) kin.set_joint_value(j->name, std::clamp(0.5 * opening, j->lower, j->upper));
    kin.link_poses(q, poses);
    add_frame(at, poses,
              object_rest ? *object_rest : Eigen::Isometry3d(poses[std::size_t(kin.tip_link())] * r.grasp.inverse()));
  };

  m.object_initial = kin.tip_pose(r.start) * r.initial_grasp.inverse();
  if (!r.solved || r.path.empty()) {
    arm_frame(0, r.start, open_width, &m.object_initial);
    return m;
  }
  std::vector<Timed> pushes;
  for (const auto& p : r.pushes) pushes.push_back(timed(p.path, p.timing));
  const Timed path = timed(r.path, r.path_timing), retreat = timed(r.retreat, r.retreat_timing);
  double total = path.duration() + retreat.duration();
  for (const Timed& p : pushes) total += p.duration();
  const double period = std::max(frame_period, total / std::max(1, max_frames));

  // The pushes first, as they run: the grasping arm at the start configuration, the object carried
  // by each push from its pose before the action to its pose after while the tool is in contact.
  if (!r.pushes.empty()) {
    runtime::Kinematics pusher(robot.model, robot.model.arm_base, r.pusher_tip);
    if (pusher.joint_names() != r.pusher_joint_names)
      throw Error(r.file.string(), "/pusher_joint_names",
                  "not the chain " + robot.model.arm_base + " -> " + r.pusher_tip);
    for (std::size_t j = 0; j < r.joint_names.size(); ++j)
      pusher.set_joint_value(r.joint_names[j], r.start[Eigen::Index(j)]);
    for (const auto& [name, value] : r.joint_values)
      if (pusher.chain_slot(robot.model.joint_index(name)) < 0) pusher.set_joint_value(name, value);
    for (const Joint* j : fingers) pusher.set_joint_value(j->name, std::clamp(0.5 * r.opening, j->lower, j->upper));
    const Eigen::Isometry3d tcp = kin.tip_pose(r.start);
    for (std::size_t i = 0; i < r.pushes.size(); ++i) {
      const auto& p = r.pushes[i];
      const runtime::ObjectMotion motion =
          runtime::object_motion(tcp, p.object_before.inverse() * tcp, p.object_after.inverse() * tcp);
      const std::vector<double> at = waypoint_times(pushes[i], p.path);
      const double begin = at[std::size_t(p.begin)], end = at[std::size_t(p.end)];
      m.push_frames.push_back(m.frames);
      sample_phase(pushes[i].duration(), period, [&](double t) {
        pusher.link_poses(pushes[i].at(t), poses);
        add_frame(t, poses,
                  motion.at(end > begin ? std::clamp((t - begin) / (end - begin), 0.0, 1.0)
                            : t < begin ? 0.0
                                        : 1.0) *
                      p.object_before);
      });
      offset += pushes[i].duration();
    }
  }
  // Then the transport, the release and the retreat, the object at rest from the release on.
  const auto phase = [&](const Timed& motion, const std::vector<Eigen::VectorXd>& wps, double opening,
                         const Eigen::Isometry3d* rest) {
    const int first = m.frames;
    const int n = sample_phase(motion.duration(), period, [&](double t) { arm_frame(t, motion.at(t), opening, rest); });
    for (double t : waypoint_times(motion, wps))
      m.waypoint_frames.push_back(
          first + (t >= motion.duration() - 1e-9 ? n - 1 : std::min(n - 1, int(std::lround(t / period)))));
    offset += motion.duration();
  };
  phase(path, r.path, r.opening, nullptr);
  if (!r.retreat.empty()) {
    m.retreat_frame = m.frames;
    phase(retreat, r.retreat, r.release_opening > 0 ? r.release_opening : open_width, &r.pose);
  }
  return m;
}

}  // namespace dmgplace::tools::viewer
