#pragma once
// Everything `dmgplace bake-robot` computes, as a library call: model from URDF (+ SRDF), the
// planning chain, and the sphere model of every link.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"

namespace dmgplace::tools {

struct RobotBakeOptions {
  std::filesystem::path urdf, srdf;  // srdf may be empty
  std::vector<std::filesystem::path> package_paths;
  std::string arm_base, arm_tip;
  SphereCoverOptions spheres;
};

// The artifact without its header (the caller records parameters and input hashes).
formats::RobotArtifact bake_robot(const RobotBakeOptions& options);

}  // namespace dmgplace::tools
