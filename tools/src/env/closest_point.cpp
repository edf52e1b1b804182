#include "dmgplace/tools/env/closest_point.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

namespace dmgplace::tools {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(denom > 0)) {  // degenerate (zero-area) triangle: nearest of its edges
    Eigen::Vector3d best = a;
    for (auto [u, v] : {std::pair{&a, &b}, std::pair{&b, &c}, std::pair{&c, &a}}) {
      const Eigen::Vector3d e = *v - *u;
      const double len2 = e.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - *u).dot(e) / len2, 0.0, 1.0) : 0.0;
      const Eigen::Vector3d q = *u + t * e;
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    }
    return best;
  }
  return a + ab * (vb / denom) + ac * (vc / denom);
}

double squared_distance_to_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  return (closest_point_on_triangle(p, a, b, c) - p).squaredNorm();
}

double squared_distance_to_triangle_above(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c, double z_min) {
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
