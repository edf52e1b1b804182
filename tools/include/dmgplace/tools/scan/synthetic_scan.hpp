#pragma once
// Synthetic depth scans with known truth: a pinhole sensor's rays cast at a mesh with Embree, the
// first hits kept, Gaussian noise added. For tests and benchmarks of the scan-to-object path.
#include <Eigen/Geometry>
#include <cstdint>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/tools/io/pcd_reader.hpp"

namespace dmgplace::tools {

struct SyntheticScanOptions {
  double angular_step = 0.002;  // rad between neighbouring rays (2 mm at 1 m)
  double field_of_view = 0.6;   // rad, full width of the square image
  double noise = 0.001;         // m: standard deviation of each coordinate's Gaussian noise
  std::uint64_t seed = 1;
};

// The scan of `scene` seen from `eye` looking at `target` (the view's up is world z, or x when
// looking straight down). The viewpoint is stored as `eye`. Throws dmgplace::Error when no ray hits.
ScanCloud synthetic_scan(const TriMesh& scene, const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                         const SyntheticScanOptions& options = {});

}  // namespace dmgplace::tools
