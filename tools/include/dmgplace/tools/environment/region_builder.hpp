#pragma once
// Turns supported cells (from geometry or scans) into placement regions: height levels,
// 8-connected components, a minimum area, and splitting of large surfaces.
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"

namespace dmgplace::tools {

struct RegionOptions {
  double resolution = 0.01;        // cell edge (m)
  double max_tilt_deg = 10;        // a support surface's normal is within this of +z
  double min_free_height = 0.02;   // cells with less free space above are not regions (m)
  double min_area = 0.0009;        // smaller connected surfaces are dropped (m^2)
  double split_size = 0.3;         // surfaces longer than this along x or y are split (m)
  double level_tolerance = 0.005;  // cells within this height of a level's lowest belong to it (m)
};

// The cells of V's xy footprint: cell (i, j) spans origin + res * [i, i+1] x [j, j+1].
struct CellGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double resolution = 0.01;
  int nx = 0, ny = 0;
  Eigen::Vector2d center(int i, int j) const { return origin + resolution * Eigen::Vector2d(i + 0.5, j + 0.5); }
};
// Whole cells inside the volume's xy extent.
CellGrid cell_grid(const Eigen::AlignedBox3d& volume, double resolution);

// One supported, free cell: the surface height there and the free height above it.
struct SurfaceSample {
  int i = 0, j = 0;
  double z = 0;
  float free_height = 0;
};

std::vector<formats::PlacementRegion> build_regions(const CellGrid& grid, std::vector<SurfaceSample> samples,
                                                    const RegionOptions& options);

}  // namespace dmgplace::tools
