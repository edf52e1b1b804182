#pragma once
// ROBOT.h5: the kinematic tree, collision geometry, planning chain and allowed collision pairs.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/robot_model.hpp"

namespace dmgplace::formats {

inline constexpr const char* kRobotSchema = "dmgplace.robot";
inline constexpr int kRobotSchemaVersion = 2;

// One sphere of the fast collision model, in its link's frame.
struct LinkSphere {
  int link = -1;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0;
};

struct RobotArtifact {
  ArtifactHeader header;
  RobotModel model;
  std::vector<LinkSphere> spheres;  // union contains every link's collision geometry
};

void save_robot(RobotArtifact artifact, const std::filesystem::path& path);
RobotArtifact load_robot(const std::filesystem::path& path);
std::vector<std::string> check_robot(const RobotArtifact& a);
Summary summarize_robot(const RobotArtifact& a);

}  // namespace dmgplace::formats
