#include "dmgplace/runtime/placement/artifact_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace dmgplace::runtime {
namespace {
std::string metres(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v << " m";
  return s.str();
}

// Distance from the base origin to the nearest point of a region's cell rectangle at its height.
double nearest(const formats::PlacementRegion& r) {
  const Eigen::Vector2d lo = r.origin, hi = r.origin + r.resolution * Eigen::Vector2d(r.width, r.depth);
  const Eigen::Vector2d p = Eigen::Vector2d::Zero().cwiseMax(lo).cwiseMin(hi);
  return Eigen::Vector3d(p.x(), p.y(), r.height).norm();
}
}  // namespace

double reach_bound(const Kinematics& kin) {
  const auto& m = kin.model();
  double reach = 0;
  for (int link = kin.tip_link(); link != kin.base_link();) {
    const auto it = std::find_if(m.joints.begin(), m.joints.end(), [&](const Joint& j) { return j.child == link; });
    if (it == m.joints.end()) break;  // the tip descends from the base (Kinematics checked it)
    reach += it->origin.translation().norm();
    if (it->type == JointType::Prismatic) reach += std::max(std::abs(it->lower), std::abs(it->upper));
    link = it->parent;
  }
  return reach;
}

ArtifactFit check_fit(const formats::ObjectArtifact& object, const std::vector<formats::PlacementRegion>& regions,
                      const Kinematics& kin, double robot_max_opening, int fingers, const FitNames& names) {
  ArtifactFit fit;
  // Gripper: the DMG's grasps may be as wide as its gripper model opens.
  const double dmg_opening = object.dmg.gripper.max_opening;
  constexpr double kOpeningSlack = 0.005;
  if (fingers < 2) {
    fit.warnings.push_back(names.robot + ": the hand has " + std::to_string(fingers) +
                           " finger links behind a movable joint; the gripper opening against " + names.object +
                           " is not checked");
  } else if (dmg_opening > robot_max_opening + kOpeningSlack) {
    fit.errors.push_back(names.object + " and " + names.robot + ": the object's DMG was built for a gripper opening " +
                         metres(dmg_opening) + ", the robot's fingers open " + metres(robot_max_opening) +
                         " (bake the object with this robot's gripper: bake-object --gripper)");
  } else if (dmg_opening < 0.5 * robot_max_opening) {
    fit.warnings.push_back(names.object + " and " + names.robot + ": the DMG's gripper opens " + metres(dmg_opening) +
                           ", half the robot's " + metres(robot_max_opening) + " or less: wider grasps are missing");
  }
  // Reach: some region the arm can possibly get to.
  if (!regions.empty()) {
    const double reach = reach_bound(kin);
    double closest = std::numeric_limits<double>::infinity();
    for (const auto& r : regions) closest = std::min(closest, nearest(r));
    if (closest > reach)
      fit.errors.push_back(names.environment + " and " + names.robot + ": the nearest placement region is " +
                           metres(closest) + " from the arm's base, beyond its reach of at most " + metres(reach) +
                           " (a frame mismatch? bake-env --frame places the scene in the robot's base frame)");
  }
  // Units.
  if (!object.mesh.empty()) {
    const Eigen::Vector3d size = object.mesh.vertices.colwise().maxCoeff() - object.mesh.vertices.colwise().minCoeff();
    if (size.norm() > 2.0)
      fit.warnings.push_back(names.object + ": " + metres(size.norm()) +
                             " across: a mesh in millimetres baked without --scale 0.001?");
    if (size.norm() < 0.005)
      fit.warnings.push_back(names.object + ": " + metres(size.norm()) + " across: a mesh in metres scaled twice?");
  }
  return fit;
}

}  // namespace dmgplace::runtime
