#pragma once
// A robot as a tree of links and joints (from URDF/SRDF), the value stored in ROBOT.h5.
#include <string>
#include <utility>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats {

enum class JointType : int { Fixed = 0, Revolute = 1, Continuous = 2, Prismatic = 3 };

struct Link {
  std::string name;
  std::vector<Shape> collision;  // in the link frame
};

struct Joint {
  std::string name;
  JointType type = JointType::Fixed;
  int parent = -1;                                           // link index
  int child = -1;                                            // link index
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // child frame in parent frame at q = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();           // unit, in the joint frame
  double lower = 0, upper = 0, velocity = 0;
  double acceleration = 0;  // max |q''| (joint_limits.yaml); 0: not given, timing uses its default
  int mimic = -1;           // joint index this one follows: q = multiplier * q_mimic + offset
  double mimic_multiplier = 1, mimic_offset = 0;
};

struct RobotModel {
  std::string name;
  std::vector<Link> links;
  std::vector<Joint> joints;
  std::string arm_base, arm_tip;                   // the planning chain
  std::vector<std::pair<int, int>> allowed_pairs;  // link pairs never checked against each other

  int link_index(const std::string& n) const {
    for (std::size_t i = 0; i < links.size(); ++i)
      if (links[i].name == n) return int(i);
    return -1;
  }
  int joint_index(const std::string& n) const {
    for (std::size_t i = 0; i < joints.size(); ++i)
      if (joints[i].name == n) return int(i);
    return -1;
  }
};

}  // namespace dmgplace::formats

// The runtime and tools use the robot model unqualified, from namespace dmgplace.
namespace dmgplace {
using formats::Joint;
using formats::JointType;
using formats::Link;
using formats::RobotModel;
}  // namespace dmgplace
