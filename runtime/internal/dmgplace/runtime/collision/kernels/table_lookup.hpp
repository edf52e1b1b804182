#pragma once
// A self-distance table (a body pair's proven distance over at most two joints, on a grid) read
// for 8 configurations in double lanes, four at a time: per lane the nearest node (clamped to the
// grid), the slope times the way there, and the node's value. The same answers as the scalar
// lookup (formats::SelfDistanceTable::lower_bound on values in tenths of a millimetre).
#include <array>
#include <cstdint>

#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime::kernels {

struct TableLanes {
  const int* slot;  // q indices of the table's joints; slot[1] = -1 for a 1-D table
  const std::array<double, 2>& lower;
  const std::array<double, 2>& step;
  const double* inv_step;  // 1 / step
  const std::array<double, 2>& slope;
  const std::array<int, 2>& count;
  const std::uint16_t* tenths_mm;  // count[0] x count[1] values, row-major, tenths of a mm rounded down
};

// Bit k set where the table's bound at q[k] (8 configurations) is above `padding`.
inline __attribute__((always_inline)) std::uint32_t table_apart(const TableLanes& t, const double* const* q,
                                                                double padding, bool wide) {
  using lanes::D;
  typedef int I __attribute__((vector_size(4 * sizeof(int))));
  std::uint32_t out = 0;
  for (int h = 0; h < lanes::WF; h += lanes::W) {  // 8 configurations, 4 per double vector
    D loss{};
    I index{};
    for (std::size_t k = 0; k < 2; ++k) {
      const int at = t.slot[k];
      const D x = at >= 0 ? D{q[h][at], q[h + 1][at], q[h + 2][at], q[h + 3][at]} : D{};
      const D lower = lanes::splat(t.lower[k]);
      D u = (x - lower) * lanes::splat(t.inv_step[k]);
      u = u > D{} ? u : D{};  // also maps NaN to 0
      u = lanes::min(u, lanes::splat(double(t.count[k] - 1)));
      const I i = __builtin_convertvector(u + lanes::splat(0.5), I);  // u >= 0: truncation rounds
      loss +=
          lanes::splat(t.slope[k]) * lanes::abs(x - (lower + __builtin_convertvector(i, D) * lanes::splat(t.step[k])));
      index = index * t.count[k] + i;
    }
    const D value = D{double(t.tenths_mm[std::size_t(index[0])]), double(t.tenths_mm[std::size_t(index[1])]),
                      double(t.tenths_mm[std::size_t(index[2])]), double(t.tenths_mm[std::size_t(index[3])])};
    out |= lanes::bits((lanes::M)(lanes::splat(1e-4) * value - loss - lanes::splat(padding) > D{}), wide) << h;
  }
  return out;
}

}  // namespace dmgplace::runtime::kernels
