#pragma once
// An environment artifact turned into what queries use: distance fields as interpolating grids
// (trilinear value + gradient) and the placement regions.
#include <memory>
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/runtime/geometry/grid3.hpp"

namespace dmgplace::runtime {

struct EnvironmentModel {
  Eigen::AlignedBox3d volume;
  std::shared_ptr<const Grid3> sdf;  // null when the artifact has none
  double sdf_band = 0;
  bool sdf_signed = true;
  std::shared_ptr<const Grid3> clearance;  // null when the artifact has none
  double clearance_band = 0;
  std::vector<formats::PlacementRegion> regions;
};

Grid3 to_grid(const formats::FieldGrid& field);
// Moves the grids' samples out of `artifact` (no copy of the large arrays).
EnvironmentModel make_environment_model(formats::EnvironmentArtifact&& artifact);

}  // namespace dmgplace::runtime
