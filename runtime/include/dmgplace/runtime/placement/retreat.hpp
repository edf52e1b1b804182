#pragma once
// Beyond the paper (the limitation its authors name): after release the gripper must get away.
// With the object left at its placement (an obstacle now, fingers allowed to touch it), the TCP
// withdraws straight back along its approach axis; every segment is checked exactly.
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime {

struct Retreat {
  bool ok = false;
  std::string reason;  // why not
  JointPath path;      // from the placement configuration out
};

Retreat plan_retreat(const Kinematics& kin, const ExactChecker& released, const Eigen::VectorXd& q_place,
                     double distance, double resolution);

}  // namespace dmgplace::runtime
