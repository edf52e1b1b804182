#pragma once
// The offline environment analysis behind `dmgplace bake-env`: distance fields and placement
// regions for the scene and volume of an environment artifact.
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/tools/system/progress.hpp"
#include "dmgplace/tools/environment/region_builder.hpp"

namespace dmgplace::tools {

struct EnvironmentBakeOptions {
  double resolution = 0.01;            // distance grid and region cells (m)
  double band = 0.10;                  // distance field clamp (m)
  double margin = 0.05;                // the distance grid covers V grown by this (m)
  double sdf_resolution = 0;           // distance grid cell (m); <= 0: `resolution`
  double clearance_resolution = 0.02;  // clearance grid (m)
  double clearance_band = 0;           // clearance clamp (m); 0: the target volume's diagonal
  double scan_voxel = 0.005;           // scan points kept per voxel of this edge (m); <= 0 keeps all
  RegionOptions regions;               // its resolution is replaced by `resolution`
  int segments = 32;                   // polygon segments of tessellated cylinders and spheres
  int threads = 0;                     // <= 0: all cores
  ProgressFn progress;                 // the two fields' blocks as they are done
};

// Fills env.sdf, env.sdf_signed, env.clearance and env.regions from env.scene and env.volume,
// and voxel-filters env.scene.points. Bad options or volume: dmgplace::Error naming them.
void bake_environment(formats::EnvironmentArtifact& env, const EnvironmentBakeOptions& options);

}  // namespace dmgplace::tools
