#pragma once
// The one convention for a pose a person writes (query files, --tcp, --initial, the viewer's
// result.json, Python): x, y, z in metres, then the quaternion qx, qy, qz, qw, of any non-zero
// length (it is normalised). Roll-pitch-yaw only where a flag says so (--frame): radians about
// the fixed x, then y, then z axes, as URDF's rpy.
#include <Eigen/Geometry>
#include <span>
#include <string>

namespace dmgplace::formats {

// Throws dmgplace::Error(file, element, ...) for a non-finite value or a quaternion shorter than 1e-6.
Eigen::Isometry3d pose_from_xyz_quaternion(std::span<const double, 7> v, const std::string& file,
                                           const std::string& element);
Eigen::Isometry3d pose_from_xyz_rpy(std::span<const double, 6> v, const std::string& file, const std::string& element);

}  // namespace dmgplace::formats
