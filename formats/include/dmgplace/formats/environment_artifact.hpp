#pragma once
// ENV.h5: an environment's exact collision geometry and its target volume.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats {

inline constexpr const char* kEnvironmentSchema = "dmgplace.environment";
inline constexpr int kEnvironmentSchemaVersion = 1;

struct EnvironmentArtifact {
  ArtifactHeader header;
  Scene scene;                 // obstacles in the world frame (z up), scan points if any
  Eigen::AlignedBox3d volume;  // the target volume V
};

void save_environment(EnvironmentArtifact artifact, const std::filesystem::path& path);
EnvironmentArtifact load_environment(const std::filesystem::path& path);
std::vector<std::string> check_environment(const EnvironmentArtifact& a);
Summary summarize_environment(const EnvironmentArtifact& a);

}  // namespace dmgplace::formats
