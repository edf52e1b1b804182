#include "dmgplace/tools/environment/closest_point.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "dmgplace/formats/triangle_distance.hpp"

namespace dmgplace::tools {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c) {
  return formats::closest_point_on_triangle(p, a, b, c);
}

double squared_distance_to_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  return (closest_point_on_triangle(p, a, b, c) - p).squaredNorm();
}

double squared_distance_to_triangle_above(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, double z_min) {
  const double lo = std::min({a.z(), b.z(), c.z()}), hi = std::max({a.z(), b.z(), c.z()});
  if (hi <= z_min) return std::numeric_limits<double>::infinity();
  if (lo > z_min) return squared_distance_to_triangle(p, a, b, c);
  // Clip against z > z_min (Sutherland-Hodgman): at most a quadrilateral, fanned into triangles.
  const std::array<const Eigen::Vector3d*, 3> in = {&a, &b, &c};
  std::array<Eigen::Vector3d, 4> poly;
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& u = *in[std::size_t(k)];
    const Eigen::Vector3d& v = *in[std::size_t((k + 1) % 3)];
    const bool u_in = u.z() > z_min, v_in = v.z() > z_min;
    if (u_in) poly[std::size_t(n++)] = u;
    if (u_in != v_in && n < 4) poly[std::size_t(n++)] = u + (v - u) * ((z_min - u.z()) / (v.z() - u.z()));
  }
  double best = std::numeric_limits<double>::infinity();
  for (int k = 1; k + 1 < n; ++k)
    best = std::min(best, squared_distance_to_triangle(p, poly[0], poly[std::size_t(k)], poly[std::size_t(k + 1)]));
  return best;
}

}  // namespace dmgplace::tools
