#pragma once
// A planar 3R arm, joints j1-j3 in [-2.5, 2.5], links 0.4 m: for tests where only the joint space
// (and a test's own validity function over it) matters.
#include <string>

#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::test {

inline RobotModel planar_3r() {
  RobotModel m;
  m.name = "planar3";
  for (auto n : {"base", "l1", "l2", "l3"}) m.links.push_back({n, {}});
  for (int j = 0; j < 3; ++j) {
    Joint jt;
    jt.name = "j" + std::to_string(j + 1);
    jt.type = JointType::Revolute;
    jt.parent = j;
    jt.child = j + 1;
    jt.lower = -2.5;
    jt.upper = 2.5;
    if (j > 0) jt.origin.translation() = Eigen::Vector3d(0.4, 0, 0);
    m.joints.push_back(jt);
  }
  return m;
}

}  // namespace dmgplace::test
