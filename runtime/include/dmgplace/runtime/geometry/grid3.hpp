#pragma once
// A regular 3-D grid of float samples (distance fields) with trilinear interpolation and its
// exact gradient. Samples sit at origin + resolution * (i, j, k); x varies fastest in `values`.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace dmgplace::runtime {

class Grid3 {
 public:
  Grid3() = default;
  Grid3(const Eigen::Vector3d& origin, double resolution, const std::array<int, 3>& dims, float fill = 0.f);

  const Eigen::Vector3d& origin() const { return origin_; }
  double resolution() const { return resolution_; }
  const std::array<int, 3>& dims() const { return dims_; }
  std::vector<float>& values() { return values_; }
  const std::vector<float>& values() const { return values_; }
  std::size_t index(int i, int j, int k) const {
    return std::size_t(i) + std::size_t(dims_[0]) * (std::size_t(j) + std::size_t(dims_[1]) * std::size_t(k));
  }
  float at(int i, int j, int k) const { return values_[index(i, j, k)]; }
  Eigen::Vector3d point(int i, int j, int k) const { return origin_ + resolution_ * Eigen::Vector3d(i, j, k); }

  // Trilinear value at p; points outside the grid are clamped onto its boundary (so far-field
  // queries return the boundary band value and a gradient of the clamped axis of zero).
  double sample(const Eigen::Vector3d& p) const;
  double sample(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const;

 private:
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double resolution_ = 1.0;
  double inv_resolution_ = 1.0;
  std::array<int, 3> dims_{0, 0, 0};
  std::vector<float> values_;
};

}  // namespace dmgplace::runtime
