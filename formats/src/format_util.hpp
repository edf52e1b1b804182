#pragma once
// Small helpers for the artifact kinds (private to dmgplace_formats).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/h5_writer.hpp"

namespace dmgplace::formats::detail {

inline void write_mesh(H5Writer& w, const std::string& g, const TriMesh& m) {
  w.write(g + "/vertices", std::span<const double>(m.vertices.data(), std::size_t(m.vertices.size())),
          {std::size_t(m.vertices.rows()), 3});
  w.write(g + "/triangles", std::span<const std::int32_t>(m.triangles.data(), std::size_t(m.triangles.size())),
          {std::size_t(m.triangles.rows()), 3});
}

inline TriMesh read_mesh(const H5Reader& r, const std::string& g) {
  auto v = r.read_f64(g + "/vertices", {-1, 3});
  auto t = r.read_i32(g + "/triangles", {-1, 3});
  TriMesh m;
  m.vertices = Eigen::Map<const RowMatrixX3d>(v.data.data(), Eigen::Index(v.rows()), 3);
  m.triangles = Eigen::Map<const RowMatrixX3i>(t.data.data(), Eigen::Index(t.rows()), 3);
  return m;
}

inline std::vector<std::string> check_mesh_indices(const TriMesh& m, const std::string& where) {
  std::vector<std::string> p;
  if (m.empty()) p.push_back(where + ": empty mesh");
  if (!m.vertices.allFinite()) p.push_back(where + ": non-finite vertex");
  if (m.triangles.size() > 0 && (m.triangles.minCoeff() < 0 || m.triangles.maxCoeff() >= m.vertices.rows()))
    p.push_back(where + ": triangle index out of range");
  return p;
}

inline std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}
inline std::string fmt(const Eigen::Vector3d& v) {
  return "[" + fmt(v.x()) + ", " + fmt(v.y()) + ", " + fmt(v.z()) + "]";
}

inline void append(std::vector<std::string>& a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
}

// A finite proper rotation (a stored zero quaternion gives a zero matrix, not a rotation).
inline bool is_rotation(const Eigen::Matrix3d& r) {
  return r.allFinite() && (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() <= 1e-6 && r.determinant() > 0;
}

// [first, first + count) inside [0, size), without forming first + count (a crafted INT64_MAX
// overflowed the sum before the comparison could refuse it).
inline bool range_within(std::int64_t first, std::int64_t count, std::size_t size) {
  return first >= 0 && count >= 0 && std::uint64_t(first) <= size &&
         std::uint64_t(count) <= size - std::uint64_t(first);
}

// The loaders' semantic gate: an artifact with any problem is refused, naming the file and the
// first few problems (`dmgplace validate FILE` lists them all).
inline void require_sound(const std::string& file, const std::vector<std::string>& problems) {
  if (problems.empty()) return;
  constexpr std::size_t kShown = 3;
  std::string m = problems.front();
  for (std::size_t i = 1; i < std::min(problems.size(), kShown); ++i) m += "; " + problems[i];
  if (problems.size() > kShown) m += "; and " + std::to_string(problems.size() - kShown) + " more";
  throw Error(file, "", m + " (refused: `dmgplace validate` lists every problem)");
}

// A stored count or index as an int, refusing NaN, fractions and values outside [lo, hi] before
// any cast (a cast of an out-of-range double is undefined behaviour).
inline int checked_int(double v, double lo, double hi, const std::string& file, const std::string& element) {
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    throw Error(file, element,
                "value " + std::to_string(v) + " is not an integer in [" + std::to_string(long(lo)) + ", " +
                    std::to_string(long(hi)) + "]");
  return int(v);
}

}  // namespace dmgplace::formats::detail
