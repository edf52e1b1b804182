#pragma once
// Is the whole gripper (both fingers and the palm) free of the object for one grasp? Exact box /
// triangle tests through Embree (private to dmgplace_tools).
#include <Eigen/Geometry>

#include "dmgplace/formats/object_artifact.hpp"
#include "embree_mesh.hpp"

namespace dmgplace::tools::detail {

class GripperCheck {
 public:
  GripperCheck(const EmbreeMesh& mesh, const Eigen::AlignedBox3d& object_box, const formats::GripperModel& g);
  // Finger 1 touches p (outward normal n), finger 2 touches q on the ray p - t n; `approach` is the
  // gripper z axis (unit, perpendicular to n). Pads are placed contact_tolerance off the surface.
  bool free(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
            const Eigen::Vector3d& approach) const;

 private:
  bool box_free(const OrientedBox& b) const;
  const EmbreeMesh& mesh_;
  Eigen::AlignedBox3d object_box_;
  formats::GripperModel g_;
  std::vector<OrientedBox> palm_parts_;  // the palm cut into pieces so each Embree query stays local
};

}  // namespace dmgplace::tools::detail
