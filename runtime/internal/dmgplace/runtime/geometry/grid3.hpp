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
  // Takes `values` (x fastest, then y, then z) as they are: no fill, no copy.
  Grid3(const Eigen::Vector3d& origin, double resolution, const std::array<int, 3>& dims, std::vector<float>&& values);

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

// Inline: the hot path of collision checks, without the gradient's extra work.
inline double Grid3::sample(const Eigen::Vector3d& p) const {
  int c[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    double u = (p[a] - origin_[a]) * inv_resolution_;
    u = u > 0 ? u : 0.0;  // also maps NaN to 0
    const double hi = double(dims_[a] - 1);
    u = u < hi ? u : hi;
    int i = int(u);
    i = i < dims_[a] - 2 ? i : dims_[a] - 2;
    c[a] = i;
    t[a] = u - i;
  }
  const float* v = values_.data() + index(c[0], c[1], c[2]);
  const std::size_t sy = std::size_t(dims_[0]), sz = std::size_t(dims_[0]) * std::size_t(dims_[1]);
  const double x = t[0];
  const double c00 = v[0] + (v[1] - v[0]) * x, c10 = v[sy] + (v[sy + 1] - v[sy]) * x;
  const double c01 = v[sz] + (v[sz + 1] - v[sz]) * x, c11 = v[sy + sz] + (v[sy + sz + 1] - v[sy + sz]) * x;
  const double c0 = c00 + (c10 - c00) * t[1], c1 = c01 + (c11 - c01) * t[1];
  return c0 + (c1 - c0) * t[2];
}

}  // namespace dmgplace::runtime
