#include "dmgplace/formats/pose_input.hpp"

#include <cmath>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::formats {

Eigen::Isometry3d pose_from_xyz_quaternion(std::span<const double, 7> v, const std::string& file,
                                           const std::string& element) {
  for (double x : v)
    if (!std::isfinite(x)) throw Error(file, element, "not a finite number");
  const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
  if (q.norm() < 1e-6) throw Error(file, element, "zero quaternion (qx, qy, qz, qw must not all be 0)");
  return Eigen::Translation3d(v[0], v[1], v[2]) * q.normalized();
}

Eigen::Isometry3d pose_from_xyz_rpy(std::span<const double, 6> v, const std::string& file, const std::string& element) {
  for (double x : v)
    if (!std::isfinite(x)) throw Error(file, element, "not a finite number");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  t.linear() = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return t;
}

}  // namespace dmgplace::formats
