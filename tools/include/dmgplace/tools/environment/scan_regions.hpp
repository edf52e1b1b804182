#pragma once
// Support surfaces of a point-cloud scan (world frame, z up): PCL normals, horizontal planes by
// RANSAC (perpendicular-plane model), rasterised on V's cells; cells with scan points standing on
// them (clutter) closer above than the minimum free height are removed.
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/tools/environment/region_builder.hpp"

namespace dmgplace::tools {

std::vector<SurfaceSample> scan_surface_samples(const RowMatrixX3d& points, const Eigen::AlignedBox3d& volume,
                                                const CellGrid& grid, const RegionOptions& options);

// Keeps one point (the centroid) per occupied cube of edge `leaf` (PCL VoxelGrid).
RowMatrixX3d voxel_filter(const RowMatrixX3d& points, double leaf);

}  // namespace dmgplace::tools
