#include "dmgplace/runtime/geometry/capsule.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace dmgplace::runtime {

std::optional<Capsule> bounding_capsule(const std::vector<Eigen::Vector3d>& centers, const std::vector<double>& radii) {
  const std::size_t n = centers.size();
  if (n < 2 || radii.size() != n) return std::nullopt;
  for (std::size_t i = 0; i < n; ++i)
    if (!centers[i].allFinite() || !std::isfinite(radii[i]) || radii[i] < 0) return std::nullopt;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : centers) mean += c;
  mean /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& c : centers) cov += (c - mean) * (c - mean).transpose();
  // The principal axis: the centers spread most along it, so the segment takes up their length.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d axis = eig.eigenvectors().col(2).normalized();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& c : centers) {
    lo = std::min(lo, (c - mean).dot(axis));
    hi = std::max(hi, (c - mean).dot(axis));
  }
  if (!(hi > lo) || !axis.allFinite()) return std::nullopt;
  Capsule k;
  k.from = mean + lo * axis;
  k.to = mean + hi * axis;
  for (std::size_t i = 0; i < n; ++i)
    k.radius = std::max(k.radius, distance_to_segment(centers[i], k.from, k.to) + radii[i]);
  k.radius += 1e-9 * (1 + k.radius);  // the distances' own rounding, rounded up
  return k;
}

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const Eigen::Vector3d d = to - from;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - from).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - from - t * d).norm();
}

}  // namespace dmgplace::runtime
