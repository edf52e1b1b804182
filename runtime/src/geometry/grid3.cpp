#include "dmgplace/runtime/geometry/grid3.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dmgplace::runtime {

Grid3::Grid3(const Eigen::Vector3d& origin, double resolution, const std::array<int, 3>& dims, float fill)
    : origin_(origin), resolution_(resolution), inv_resolution_(1.0 / resolution), dims_(dims) {
  if (!(resolution > 0) || dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
    throw std::invalid_argument("Grid3 needs a positive resolution and at least 2 samples per axis");
  values_.assign(std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]), fill);
}

Grid3::Grid3(const Eigen::Vector3d& origin, double resolution, const std::array<int, 3>& dims,
             std::vector<float>&& values)
    : origin_(origin), resolution_(resolution), inv_resolution_(1.0 / resolution), dims_(dims) {
  if (!(resolution > 0) || dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
    throw std::invalid_argument("Grid3 needs a positive resolution and at least 2 samples per axis");
  if (values.size() != std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]))
    throw std::invalid_argument("Grid3 values do not match its dimensions");
  values_ = std::move(values);
}

double Grid3::sample(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const {
  int c[3];
  double t[3];
  bool clamped[3];
  for (int a = 0; a < 3; ++a) {
    double u = (p[a] - origin_[a]) / resolution_;
    const double hi = double(dims_[a] - 1);
    clamped[a] = !(u >= 0 && u <= hi);  // NaN counts as clamped
    u = std::clamp(std::isnan(u) ? 0.0 : u, 0.0, hi);
    int i = std::min(int(u), dims_[a] - 2);
    c[a] = i;
    t[a] = u - i;
  }
  const float* v = values_.data();
  const std::size_t sx = 1, sy = std::size_t(dims_[0]), sz = std::size_t(dims_[0]) * std::size_t(dims_[1]);
  const std::size_t b = index(c[0], c[1], c[2]);
  const double v000 = v[b], v100 = v[b + sx], v010 = v[b + sy], v110 = v[b + sx + sy];
  const double v001 = v[b + sz], v101 = v[b + sx + sz], v011 = v[b + sy + sz], v111 = v[b + sx + sy + sz];
  const double x = t[0], y = t[1], z = t[2];
  const double c00 = v000 + (v100 - v000) * x, c10 = v010 + (v110 - v010) * x;
  const double c01 = v001 + (v101 - v001) * x, c11 = v011 + (v111 - v011) * x;
  const double c0 = c00 + (c10 - c00) * y, c1 = c01 + (c11 - c01) * y;
  const double dx0 = (v100 - v000) + ((v110 - v010) - (v100 - v000)) * y;
  const double dx1 = (v101 - v001) + ((v111 - v011) - (v101 - v001)) * y;
  gradient.x() = clamped[0] ? 0.0 : (dx0 + (dx1 - dx0) * z) / resolution_;
  gradient.y() = clamped[1] ? 0.0 : ((c10 - c00) + ((c11 - c01) - (c10 - c00)) * z) / resolution_;
  gradient.z() = clamped[2] ? 0.0 : (c1 - c0) / resolution_;
  return c0 + (c1 - c0) * z;
}

}  // namespace dmgplace::runtime
