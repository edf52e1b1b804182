#pragma once
// Point-to-triangle distances in double precision (the exact part behind the Embree queries).
#include <Eigen/Core>

namespace dmgplace::tools {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);
double squared_distance_to_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c);
// Squared distance from p to the part of triangle abc strictly above height z_min; +inf if none.
double squared_distance_to_triangle_above(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, double z_min);

}  // namespace dmgplace::tools
