#include "dmgplace/runtime/collision/node_bound_grid.hpp"

#include <algorithm>
#include <cmath>

namespace dmgplace::runtime {

NodeBoundGrid::NodeBoundGrid(const Grid3& g, int stride)
    : origin_(g.origin()), res_(g.resolution() * stride), inv_(1.0 / (g.resolution() * stride)) {
  for (int a = 0; a < 3; ++a) dims_[std::size_t(a)] = (g.dims()[std::size_t(a)] - 1) / stride + 1;
  values_.resize(std::size_t(dims_[0]) * std::size_t(dims_[1]) * std::size_t(dims_[2]));
  std::size_t n = 0;
  for (int k = 0; k < dims_[2]; ++k)
    for (int j = 0; j < dims_[1]; ++j)
      for (int i = 0; i < dims_[0]; ++i) {
        // Rounded down (and a step lower for float rounding of the product): never above the value.
        const double steps = std::floor(double(g.at(i * stride, j * stride, k * stride)) / kUnit) - 1.0;
        values_[n++] = std::int16_t(std::clamp(steps, -32768.0, 32767.0));
      }
}

}  // namespace dmgplace::runtime
