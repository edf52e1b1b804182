#pragma once
// Beyond the paper (the limitation its authors name): after release the gripper must get away.
// With the object left at its placement (an obstacle now, fingers allowed to touch it), the TCP
// withdraws in a straight line along `direction` (base frame: the planner tries back along the
// approach axis, then straight up), orientation kept; every segment is checked exactly at the
// segment checker's states. With `clear`, the withdrawal ends at the first step where clear(q)
// holds (the hand no longer touches the object); from there retreat_motion.hpp plans the rest.
#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime {

struct Retreat {
  bool ok = false;
  std::string reason;  // why not
  JointPath path;      // from the placement configuration out
};

Retreat plan_retreat(const Kinematics& kin, const ExactChecker& released, const Eigen::VectorXd& q_place,
                     const Eigen::Vector3d& direction, double distance, double resolution,
                     const ValidityFn& clear = nullptr);

}  // namespace dmgplace::runtime
