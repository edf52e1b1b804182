#pragma once
// Reads point-cloud scans (PCD: ascii, binary, binary_compressed) through PCL.
#include <Eigen/Geometry>
#include <filesystem>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

// The x, y, z of every finite point (NaN/Inf points, e.g. holes of organized clouds, dropped).
// Missing file, malformed or truncated data, no x/y/z fields, or no finite point: dmgplace::Error.
RowMatrixX3d read_pcd(const std::filesystem::path& pcd);

// A scene of scan points only: read_pcd's points moved into the world by `frame` (the pose of
// the cloud's frame in the world).
Scene read_scan_scene(const std::filesystem::path& pcd, const Eigen::Isometry3d& frame = Eigen::Isometry3d::Identity());

}  // namespace dmgplace::tools
