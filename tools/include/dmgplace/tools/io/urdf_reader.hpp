#pragma once
// Reads a robot (URDF through urdfdom, SRDF disabled collisions through tinyxml2) into a RobotModel.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_model.hpp"

namespace dmgplace::tools {

struct UrdfOptions {
  // Folders holding ROS packages: package://NAME/rest is looked up as P/NAME/rest, then P/rest.
  std::vector<std::filesystem::path> package_paths;
  // The link tree and joints only, no collision geometry (no mesh file is read): for comparing
  // an artifact's joint limits with its URDF.
  bool skip_collision = false;
};

// Links in depth-first order from the root (children by joint name), each joint listed after its
// parent link's joint. Collision boxes, cylinders and spheres stay primitives; meshes are read with
// read_mesh and the URDF scale. Continuous joints get the limits [-pi, pi].
// Rejected with dmgplace::Error: unreadable URDF, floating/planar joints, zero axes, NaN or inverted
// limits, unknown mimic targets, missing or broken mesh files (the error names the link).
// arm_base, arm_tip and allowed_pairs are left empty.
RobotModel read_urdf(const std::filesystem::path& urdf, const UrdfOptions& options = {});

// Adds every <disable_collisions link1 link2> of the SRDF to model.allowed_pairs (each pair once,
// smaller index first). An unknown link name is a dmgplace::Error naming it.
void apply_srdf(RobotModel& model, const std::filesystem::path& srdf);

// Sets the planning chain after checking both links exist and `tip` descends from `base`;
// `file` names the input that asked for the chain in the dmgplace::Error otherwise.
void set_arm_chain(RobotModel& model, const std::string& base, const std::string& tip, const std::string& file);

}  // namespace dmgplace::tools
