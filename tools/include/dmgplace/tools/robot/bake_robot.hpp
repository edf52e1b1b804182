#pragma once
// Everything `dmgplace bake-robot` computes, as a library call: model from URDF (+ SRDF, or the
// allowed-collision pairs computed without one), the planning chain, and the sphere model of
// every link.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/robot/allowed_collisions.hpp"
#include "dmgplace/tools/robot/self_distance_tables.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"

namespace dmgplace::tools {

struct RobotBakeOptions {
  std::filesystem::path urdf, srdf;    // srdf may be empty
  std::filesystem::path joint_limits;  // MoveIt joint_limits.yaml (may be empty): velocity/acceleration limits
  std::vector<std::filesystem::path> package_paths;
  std::string arm_base, arm_tip;
  // When set, a link "<arm_tip>_tcp" fixed to the tip at this pose (the gripper's tool center
  // point: z approach, y closing) is added and becomes the chain's tip; the placement planner
  // needs the tip there (the Panda URDF, for one, has no such frame).
  std::optional<Eigen::Isometry3d> tcp;
  // Joints outside the planning chain frozen at these values (rad or m): they become fixed
  // joints, so the rest of the robot (another arm, a torso) stands where the user says.
  std::vector<std::pair<std::string, double>> fixed_joints;
  SphereCoverOptions spheres;
  SelfTableOptions self_tables;
  AllowedCollisionOptions allowed;  // used when there is no SRDF
};

// The artifact without its header (the caller records parameters and input hashes). Without an
// SRDF the allowed-collision pairs are computed (allowed_collisions.hpp) and, when `decided` is
// given, returned there. `notes` (optional) gets what an input held that the bake does not use.
formats::RobotArtifact bake_robot(const RobotBakeOptions& options, AllowedCollisions* decided = nullptr,
                                  std::vector<std::string>* notes = nullptr);

}  // namespace dmgplace::tools
