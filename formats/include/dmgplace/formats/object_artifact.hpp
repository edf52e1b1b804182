#pragma once
// OBJECT.h5: everything the runtime needs about one rigid object.
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats {

inline constexpr const char* kObjectSchema = "dmgplace.object";
inline constexpr int kObjectSchemaVersion = 1;

struct MassProperties {
  double volume = 0;                                    // m^3, from the closed mesh
  double mass = 0;                                      // kg
  Eigen::Vector3d com = Eigen::Vector3d::Zero();        // object frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();    // about the COM, kg m^2
  bool com_overridden = false;                          // --com given by the user
};

struct ObjectArtifact {
  ArtifactHeader header;  // schema fields are filled by save/load
  TriMesh mesh;           // object frame, metres
  MassProperties mass;
};

void save_object(ObjectArtifact artifact, const std::filesystem::path& path);
ObjectArtifact load_object(const std::filesystem::path& path);
std::vector<std::string> check_object(const ObjectArtifact& a);
Summary summarize_object(const ObjectArtifact& a);

}  // namespace dmgplace::formats
