#pragma once
// Numeric inverse kinematics: Levenberg-Marquardt (adaptive damped least squares) with joint
// limits, started from a seed and then from random restarts.
#include <random>
#include <string>

#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::runtime {

struct IkOptions {
  double position_tolerance = 1e-4;     // metres
  double orientation_tolerance = 1e-3;  // radians
  int max_iterations = 60;              // per start
  int max_restarts = 30;                // random starts after the seed
  double orientation_weight = 0.3;      // metres per radian in the error norm
};

struct IkResult {
  bool success = false;
  Eigen::VectorXd q;
  std::string reason;  // why it failed: "not converged", "joint limits", "invalid target"
  double position_error = 0, orientation_error = 0;
  int iterations = 0, starts = 0;
};

class IkSolver {
 public:
  explicit IkSolver(const Kinematics& kin, IkOptions options = {}) : kin_(kin), opt_(options) {}
  // Target: tip pose in the base frame.
  IkResult solve(const Eigen::Isometry3d& target, const Eigen::VectorXd& seed, std::mt19937_64& rng) const;

 private:
  bool descend(const Eigen::Isometry3d& target, Eigen::VectorXd& q, IkResult& r) const;
  const Kinematics& kin_;
  IkOptions opt_;
};

// Pose error [dp; w * dtheta] of `current` towards `target`, in the base frame.
Eigen::Matrix<double, 6, 1> pose_error(const Eigen::Isometry3d& current, const Eigen::Isometry3d& target);

}  // namespace dmgplace::runtime
