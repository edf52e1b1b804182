#pragma once
// Writes point clouds as ASCII PCD v0.7 (x y z, one point per line, the sensor pose as VIEWPOINT),
// atomically: a temporary file in the target's folder renamed into place.
#include <Eigen/Geometry>
#include <filesystem>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

void write_pcd(const std::filesystem::path& path, const RowMatrixX3d& points,
               const Eigen::Vector3d& viewpoint = Eigen::Vector3d::Zero(),
               const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity());

}  // namespace dmgplace::tools
