#pragma once
// Reads point-cloud scans (PCD: ascii, binary, binary_compressed) through PCL.
#include <Eigen/Geometry>
#include <filesystem>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

// A scan as the sensor saw it: points in the cloud frame and the sensor pose stored in the PCD
// header (VIEWPOINT: origin and orientation), which says which way each surface faced the sensor.
struct ScanCloud {
  RowMatrixX3d points;
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};
// read_pcd's points plus the header's viewpoint.
ScanCloud read_scan(const std::filesystem::path& pcd);

// The x, y, z of every finite point (NaN/Inf points, e.g. holes of organized clouds, dropped).
// Missing file, malformed or truncated data, no x/y/z fields, or no finite point: dmgplace::Error.
RowMatrixX3d read_pcd(const std::filesystem::path& pcd);

// A scene of scan points only: read_pcd's points moved into the world by `frame` (the pose of
// the cloud's frame in the world).
Scene read_scan_scene(const std::filesystem::path& pcd, const Eigen::Isometry3d& frame = Eigen::Isometry3d::Identity());

}  // namespace dmgplace::tools
