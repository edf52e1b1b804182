#include "dmgplace/tools/robot/bake_robot.hpp"

#include <cmath>

#include "../system/parallel_for.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/io/joint_limits_reader.hpp"
#include "dmgplace/tools/io/urdf_reader.hpp"

namespace dmgplace::tools {

namespace {
// Each named joint becomes a fixed joint whose origin includes its motion at the value; mimic
// joints that follow it are frozen with it.
void freeze_joints(RobotModel& m, const std::vector<std::pair<std::string, double>>& values, const std::string& file) {
  const runtime::Kinematics chain(m, m.arm_base, m.arm_tip);
  auto freeze = [&](Joint& j, double v) {
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (j.type == JointType::Prismatic) motion.translation() = j.axis * v;
    else motion.linear() = Eigen::AngleAxisd(v, j.axis).toRotationMatrix();
    j.origin = j.origin * motion;
    j.type = JointType::Fixed;
    j.mimic = -1;
  };
  for (const auto& [name, value] : values) {
    const int idx = m.joint_index(name);
    const std::string where = "--fixed-joints " + name;
    if (idx < 0) throw Error(file, where, "no joint named '" + name + "' in robot '" + m.name + "'");
    Joint& j = m.joints[std::size_t(idx)];
    if (chain.chain_slot(idx) >= 0)
      throw Error(file, where, "is a joint of the planning chain --arm; only other joints can be frozen");
    if (j.type == JointType::Fixed) throw Error(file, where, "is already a fixed joint");
    if (j.mimic >= 0)
      throw Error(file, where, "follows '" + m.joints[std::size_t(j.mimic)].name + "' (mimic): freeze that one");
    if (!std::isfinite(value) ||
        (j.type != JointType::Continuous && (value < j.lower - 1e-9 || value > j.upper + 1e-9)))
      throw Error(file, where,
                  "value " + std::to_string(value) + " outside its limits [" + std::to_string(j.lower) + ", " +
                      std::to_string(j.upper) + "]");
    for (auto& follower : m.joints)
      if (follower.mimic == idx) freeze(follower, follower.mimic_multiplier * value + follower.mimic_offset);
    freeze(j, value);
  }
}
}  // namespace

formats::RobotArtifact bake_robot(const RobotBakeOptions& o, AllowedCollisions* decided,
                                  std::vector<std::string>* notes) {
  UrdfOptions urdf;
  urdf.package_paths = o.package_paths;
  formats::RobotArtifact robot;
  robot.model = read_urdf(o.urdf, urdf);
  if (!o.srdf.empty()) apply_srdf(robot.model, o.srdf);
  if (!o.joint_limits.empty()) {
    const JointLimitsFile read = apply_joint_limits(robot.model, o.joint_limits);
    if (notes) notes->insert(notes->end(), read.notes.begin(), read.notes.end());
  }
  std::string tip = o.arm_tip;
  if (o.tcp) {
    auto& m = robot.model;
    const int parent = m.link_index(o.arm_tip);
    if (parent < 0) throw Error(o.urdf.string(), "--arm", "no link '" + o.arm_tip + "' to put the TCP on");
    tip = o.arm_tip + "_tcp";
    if (m.link_index(tip) >= 0) throw Error(o.urdf.string(), "--tcp", "the robot already has a link '" + tip + "'");
    if (!o.tcp->matrix().allFinite()) throw Error("--tcp", "", "not finite");
    m.links.push_back(Link{tip, {}});
    Joint j;
    j.name = tip + "_joint";
    j.type = JointType::Fixed;
    j.parent = parent;
    j.child = int(m.links.size()) - 1;
    j.origin = *o.tcp;
    m.joints.push_back(j);
  }
  set_arm_chain(robot.model, o.arm_base, tip, o.urdf.string());
  freeze_joints(robot.model, o.fixed_joints, o.urdf.string());
  // Without an SRDF nothing may touch, not even adjacent links: decide as MoveIt's setup
  // assistant would (the caller reports and can write what was decided).
  if (o.srdf.empty()) {
    const AllowedCollisions allowed = compute_allowed_collisions(robot.model, o.allowed);
    for (const auto& p : allowed.disabled) robot.model.allowed_pairs.emplace_back(p.a, p.b);
    if (decided) *decided = allowed;
  }
  // Each link's cover on its own (the links in parallel), then in link order; a failure names the
  // first link that failed, whichever thread saw it first.
  std::vector<std::vector<Sphere>> covers(robot.model.links.size());
  std::vector<std::string> failed(covers.size());
  detail::parallel_for(covers.size(), o.self_tables.threads, [&](std::size_t l) {
    try {
      covers[l] = cover_with_spheres(robot.model.links[l].collision, o.spheres);
    } catch (const Error& e) {
      failed[l] = e.what();
    }
  });
  for (std::size_t l = 0; l < covers.size(); ++l) {
    if (!failed[l].empty()) throw Error(o.urdf.string(), "link '" + robot.model.links[l].name + "'", failed[l]);
    for (const auto& s : covers[l]) robot.spheres.push_back({int(l), s.center, s.radius});
  }
  const runtime::Kinematics kin(robot.model, robot.model.arm_base, robot.model.arm_tip);
  robot.self_tables = build_self_distance_tables(kin, robot.spheres, o.self_tables);
  return robot;
}

}  // namespace dmgplace::tools
