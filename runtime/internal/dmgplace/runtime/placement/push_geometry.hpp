#pragma once
// The geometry of one in-hand action as a second arm performs it: the gripper holds still (the
// grasping arm at q0) and the object moves in it from the action's first grasp to its last. Here
// that motion, as a screw about the TCP, and where a pushing tool can touch the object to drive it.
#include <Eigen/Geometry>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::runtime {

// The object's motion in the world while the TCP stays at `tcp_world`: x -> R(s)(x - pivot) +
// pivot + s * shift for s in [0, 1], R(s) the rotation by s * angle about `axis`. At s = 1 it
// takes the object from `before` to `after` exactly.
struct ObjectMotion {
  Eigen::Isometry3d before = Eigen::Isometry3d::Identity(), after = Eigen::Isometry3d::Identity();
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit
  double angle = 0;                                 // rad, >= 0
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  Eigen::Isometry3d at(double s) const;  // the motion so far (world to world)
  // Velocity (per unit s) at s of the point that was at `x` (world) when s = 0.
  Eigen::Vector3d velocity(const Eigen::Vector3d& x, double s) const;
  // Largest distance any point within `radius` of the pivot moves over s in [0, 1].
  double sweep(double radius) const { return angle * radius + shift.norm(); }
};

// The object's poses in the world at the two grasps (TCP poses in the object frame).
ObjectMotion object_motion(const Eigen::Isometry3d& tcp_world, const Eigen::Isometry3d& grasp_before,
                           const Eigen::Isometry3d& grasp_after);

// A point of the object's surface where the tool can push: the tool's tip there, pushing along
// the point's velocity, into the surface.
struct PushContact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      // world, at s = 0
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // world, unit: the point's velocity at s = 0
  double score = 0;                                     // higher first
};

// Candidate contacts on `mesh` (object frame, placed by motion.before), best first and at least
// `spacing` apart, at most `count`. A point qualifies when its velocity goes into the surface at
// the start (the outward normal against it by at least 45 degrees) and still at the end of the
// motion; the score prefers a push straight into the surface and, for a slide, a line of push
// through the pivot (no turning moment on the grasp), for a turn a long lever arm.
std::vector<PushContact> push_contacts(const TriMesh& mesh, const ObjectMotion& motion, int count, double spacing);

}  // namespace dmgplace::runtime
