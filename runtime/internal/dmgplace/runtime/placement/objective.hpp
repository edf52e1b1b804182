#pragma once
// The placement preference xi(x), maximised: a weighted sum of built-in terms evaluated on the
// object's pose in the world, with a numerical gradient in the placement's free coordinates
// (x, y and the rotation about world z through the COM).
#include <vector>

#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/runtime/collision/object_spheres.hpp"
#include "dmgplace/runtime/environment/environment_model.hpp"
#include "dmgplace/runtime/placement/placement_query.hpp"

namespace dmgplace::runtime {

class Objective {
 public:
  // `points`: where the object's clearance is averaged (object frame; its occupied cells).
  Objective(std::vector<ObjectiveTerm> terms, const EnvironmentModel& env, const formats::ObjectArtifact& object,
            std::vector<Eigen::Vector3d> points);
  double value(const Eigen::Isometry3d& object_pose) const;
  // d value / d (x, y, theta): central differences with steps of 1 mm and 5 mrad.
  Eigen::Vector3d gradient(const Eigen::Isometry3d& object_pose) const;
  // The pose moved by (dx, dy) and turned by dtheta about the vertical through the COM.
  Eigen::Isometry3d moved(const Eigen::Isometry3d& object_pose, const Eigen::Vector3d& delta) const;
  const std::vector<ObjectiveTerm>& terms() const { return terms_; }

 private:
  double clearance(const Eigen::Isometry3d& pose) const;
  std::vector<ObjectiveTerm> terms_;
  const EnvironmentModel* env_;
  Eigen::Vector3d com_;
  std::vector<Eigen::Vector3d> points_;
};

}  // namespace dmgplace::runtime
