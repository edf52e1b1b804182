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
    if (j.type == JointType::Fixed || j.mimic >= 0 || std::find(names.begin(), names.end(), j.name) != names.end()) continue;
    if (below(m, j.child, hand)) out.push_back(&j);
  }
  return out;
}

// The pusher's in-hand actions first, as they run: the grasping arm at the start configuration,
// the object carried by each push from its pose before the action to its pose after.
void push_frames(const ViewResult& r, const formats::RobotArtifact& robot, const std::vector<const Joint*>& fingers, double step,
                 ArmMotion& m) {
  if (r.pushes.empty()) return;
  runtime::Kinematics pusher(robot.model, robot.model.arm_base, r.pusher_tip);
  if (pusher.joint_names() != r.pusher_joint_names)
    throw Error(r.file.string(), "/pusher_joint_names", "not the chain " + robot.model.arm_base + " -> " + r.pusher_tip);
  const runtime::Kinematics arm(robot.model, robot.model.arm_base, robot.model.arm_tip);
  for (std::size_t j = 0; j < arm.joint_names().size(); ++j) pusher.set_joint_value(arm.joint_names()[j], r.start[Eigen::Index(j)]);
  for (const auto& [name, value] : r.joint_values)
    if (pusher.chain_slot(robot.model.joint_index(name)) < 0) pusher.set_joint_value(name, value);
  for (const Joint* j : fingers) pusher.set_joint_value(j->name, std::clamp(0.5 * r.opening, j->lower, j->upper));
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : r.pushes) {
    const Eigen::Isometry3d tcp = arm.tip_pose(r.start);
    const runtime::ObjectMotion motion = runtime::object_motion(tcp, p.object_before.inverse() * tcp, p.object_after.inverse() * tcp);
    const auto frame = [&](const Eigen::VectorXd& q, double at) {
      pusher.link_poses(q, poses);
      for (int l : m.links) push_pose(m.link_poses, poses[std::size_t(l)]);
      const double s = p.end > p.begin ? std::clamp((at - p.begin) / (p.end - p.begin), 0.0, 1.0) : 1.0;
      push_pose(m.object_poses, motion.at(s) * p.object_before);
      ++m.frames;
    };
    for (std::size_t i = 0; i < p.path.size(); ++i) {
      if (i > 0) {
        const Eigen::VectorXd d = p.path[i] - p.path[i - 1];
        const int n = std::max(1, int(std::ceil(d.cwiseAbs().maxCoeff() / step)));
        for (int k = 1; k < n; ++k) frame(p.path[i - 1] + d * (double(k) / n), double(i - 1) + double(k) / n);
      }
      frame(p.path[i], double(i));
    }
  }
}
}  // namespace

ArmMotion sample_arm_motion(const ViewResult& r, const formats::RobotArtifact& robot, double open_width, double max_step,
                            int max_frames) {
  runtime::Kinematics kin(robot.model, robot.model.arm_base, robot.model.arm_tip);
  if (kin.joint_names() != r.joint_names)
    throw Error(r.file.string(), "/joint_names", "not the arm chain of " + r.robot.string() + " (" + robot.model.arm_base +
                                                     " -> " + robot.model.arm_tip + ")");
  const auto fingers = finger_joints(kin);
  for (const auto& [name, value] : r.joint_values) kin.set_joint_value(name, value);
  ArmMotion m;
  for (std::size_t l = 0; l < robot.model.links.size(); ++l)
    if (!robot.model.links[l].collision.empty()) m.links.push_back(int(l));

  std::vector<Eigen::Isometry3d> poses;
  const auto add_frame = [&](const Eigen::VectorXd& q, double opening, const Eigen::Isometry3d* object_rest) {
    for (const Joint* j : fingers) kin.set_joint_value(j->name, std::clamp(0.5 * opening, j->lower, j->upper));
    kin.link_poses(q, poses);
    for (int l : m.links) push_pose(m.link_poses, poses[std::size_t(l)]);
    const Eigen::Isometry3d tip = poses[std::size_t(kin.tip_link())];
    push_pose(m.object_poses, object_rest ? *object_rest : Eigen::Isometry3d(tip * r.grasp.inverse()));
    ++m.frames;
  };

  m.object_initial = kin.tip_pose(r.start) * r.initial_grasp.inverse();
  if (!r.solved || r.path.empty()) {
    add_frame(r.start, open_width, &m.object_initial);
    return m;
  }
  double total = 0;
  for (const auto& p : r.pushes)
    for (std::size_t i = 1; i < p.path.size(); ++i) total += (p.path[i] - p.path[i - 1]).cwiseAbs().maxCoeff();
  for (const auto* seg : {&r.path, &r.retreat})
    for (std::size_t i = 1; i < seg->size(); ++i) total += ((*seg)[i] - (*seg)[i - 1]).cwiseAbs().maxCoeff();
  const double step = std::max(max_step, total / std::max(1, max_frames));
  const auto sweep = [&](const std::vector<Eigen::VectorXd>& wps, double opening, const Eigen::Isometry3d* rest) {
    for (std::size_t i = 0; i < wps.size(); ++i) {
      if (i > 0) {
        const Eigen::VectorXd d = wps[i] - wps[i - 1];
        const int n = std::max(1, int(std::ceil(d.cwiseAbs().maxCoeff() / step)));
        for (int k = 1; k < n; ++k) add_frame(wps[i - 1] + d * (double(k) / n), opening, rest);
      }
      m.waypoint_frames.push_back(m.frames);
      add_frame(wps[i], opening, rest);
    }
  };
  push_frames(r, robot, fingers, step, m);
  sweep(r.path, r.opening, nullptr);
  if (!r.retreat.empty()) {
    m.retreat_frame = m.frames;
    sweep(r.retreat, r.release_opening > 0 ? r.release_opening : open_width, &r.pose);
  }
  return m;
}

}  // namespace dmgplace::tools::viewer
