#pragma once
// A plain n-dimensional array as read from or written to an artifact (row-major).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dmgplace::formats {

template <class T>
struct Array {
  std::vector<T> data;
  std::vector<std::size_t> dims;

  std::size_t rows() const { return dims.empty() ? 0 : dims[0]; }
  std::size_t cols() const { return dims.size() < 2 ? 1 : dims[1]; }
  const T& operator()(std::size_t r, std::size_t c) const { return data[r * cols() + c]; }
};

}  // namespace dmgplace::formats
