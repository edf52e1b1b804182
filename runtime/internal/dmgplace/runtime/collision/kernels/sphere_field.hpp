#pragma once
// A sphere against the environment's distance grid in SIMD lanes: nearest-node lower bounds
// (node_bound_grid.hpp), coarse grid first.
#include <Eigen/Core>
#include <cstdint>

#include "dmgplace/runtime/collision/kernels/lane_points.hpp"
#include "dmgplace/runtime/collision/node_bound_grid.hpp"

namespace dmgplace::runtime::kernels {

// Lanes whose point p is at least `need` from the scene by the field (inside the grid only): the
// coarse bound where there is one, else the fine one. `alive`: lanes still worth the fine loads.
// In floats: `need` carries the margin, and the grid box is shrunk by it, so a lane inside is
// inside for its unrounded point too.
inline __attribute__((always_inline)) std::uint32_t clear_of_field(const LaneXyz& p, float need, float margin,
                                                                   std::uint32_t alive, const Eigen::Vector3d& lo,
                                                                   const Eigen::Vector3d& hi,
                                                                   const NodeBoundGrid* coarse,
                                                                   const NodeBoundGrid& fine, bool wide) {
  using lanes::F;
  using lanes::splatf;
  const F px = lanes::load(p.x), py = lanes::load(p.y), pz = lanes::load(p.z);
  auto low = [&](double v) { return splatf(float(v) + margin); };
  auto high = [&](double v) { return splatf(float(v) - margin); };
  const std::uint32_t in_grid = lanes::bits((px >= low(lo.x())) & (py >= low(lo.y())) & (pz >= low(lo.z())) &
                                                (px <= high(hi.x())) & (py <= high(hi.y())) & (pz <= high(hi.z())),
                                            wide);
  alignas(32) float b[lanes::WF];
  auto at_least_need = [&] { return lanes::bits(lanes::load(b) >= splatf(need), wide); };
  std::uint32_t ok = 0;
  if (coarse) {
    coarse->lower_bound_lanes(p.x, p.y, p.z, b);
    ok = at_least_need() & in_grid;
  }
  if ((ok & alive) != (in_grid & alive)) {
    fine.lower_bound_lanes(p.x, p.y, p.z, b);
    ok |= at_least_need();
  }
  return ok & in_grid;
}

}  // namespace dmgplace::runtime::kernels
