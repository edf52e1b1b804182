#pragma once
// Support surfaces of triangle geometry: one vertical ray per cell of V's footprint; every
// upward-facing crossing inside V's height range with free space above becomes a sample.
#include <vector>

#include "dmgplace/tools/environment/embree_scene.hpp"
#include "dmgplace/tools/environment/region_builder.hpp"

namespace dmgplace::tools {

std::vector<SurfaceSample> geometry_surface_samples(const EmbreeScene& scene, const Eigen::AlignedBox3d& volume,
                                                    const CellGrid& grid, const RegionOptions& options);

}  // namespace dmgplace::tools
