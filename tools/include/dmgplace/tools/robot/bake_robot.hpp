#pragma once
// Everything `dmgplace bake-robot` computes, as a library call: model from URDF (+ SRDF), the
// planning chain, and the sphere model of every link.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/robot/self_distance_tables.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"

namespace dmgplace::tools {

struct RobotBakeOptions {
  std::filesystem::path urdf, srdf;  // srdf may be empty
  std::vector<std::filesystem::path> package_paths;
  std::string arm_base, arm_tip;
  // When set, a link "<arm_tip>_tcp" fixed to the tip at this pose (the gripper's tool centre
  // point: z approach, y closing) is added and becomes the chain's tip; the placement planner
  // needs the tip there (the Panda URDF, for one, has no such frame).
  std::optional<Eigen::Isometry3d> tcp;
  SphereCoverOptions spheres;
  SelfTableOptions self_tables;
};

// The artifact without its header (the caller records parameters and input hashes).
formats::RobotArtifact bake_robot(const RobotBakeOptions& options);

}  // namespace dmgplace::tools
