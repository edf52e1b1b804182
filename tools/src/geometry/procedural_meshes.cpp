#include "dmgplace/tools/geometry/procedural_meshes.hpp"

#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

// Keeps vertex and triangle counts far inside int range.
constexpr int kMaxSegments = 1 << 20;

void require(bool ok, const char* what, const std::string& reason) {
  if (!ok) throw Error(what, "", reason);
}

bool positive(double v) { return std::isfinite(v) && v > 0; }

struct Ring {
  double radius;  // > 0
  double z;
};

// Revolves a profile about z: one vertex ring per profile point, closed at the bottom and the
// top by a single center vertex each. Successive rings must differ in radius or height.
TriMesh revolve(const std::vector<Ring>& rings, int segments) {
  const int n = segments;
  const int nr = static_cast<int>(rings.size());
  TriMesh m;
  m.vertices.resize(2 + nr * n, 3);
  m.triangles.resize(2 * n * nr, 3);  // two fans of n, and 2n per band between rings

  const int bottom = 0;
  const int top = 1 + nr * n;
  auto ring_vertex = [n](int k, int j) { return 1 + k * n + (j % n); };

  m.vertices.row(bottom) << 0.0, 0.0, rings.front().z;
  for (int k = 0; k < nr; ++k) {
    for (int j = 0; j < n; ++j) {
      const double a = 2.0 * std::numbers::pi * j / n;
      m.vertices.row(ring_vertex(k, j)) << rings[k].radius * std::cos(a), rings[k].radius * std::sin(a), rings[k].z;
    }
  }
  m.vertices.row(top) << 0.0, 0.0, rings.back().z;

  // Ring vertices run counter-clockwise seen from +z, so the bottom fan walks them backwards.
  int t = 0;
  for (int j = 0; j < n; ++j) m.triangles.row(t++) << bottom, ring_vertex(0, j + 1), ring_vertex(0, j);
  for (int k = 0; k + 1 < nr; ++k) {
    for (int j = 0; j < n; ++j) {
      const int a = ring_vertex(k, j), b = ring_vertex(k, j + 1);
      const int c = ring_vertex(k + 1, j + 1), d = ring_vertex(k + 1, j);
      m.triangles.row(t++) << a, b, c;
      m.triangles.row(t++) << a, c, d;
    }
  }
  for (int j = 0; j < n; ++j) m.triangles.row(t++) << top, ring_vertex(nr - 1, j), ring_vertex(nr - 1, j + 1);
  return m;
}

void check_indices(const TriMesh& mesh, const std::filesystem::path& path) {
  const Eigen::Index nv = mesh.vertices.rows();
  for (Eigen::Index i = 0; i < mesh.triangles.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles(i, c);
      if (v < 0 || v >= nv)
        throw Error(path.string(), "triangle " + std::to_string(i),
                    "vertex index " + std::to_string(v) + " out of range (" + std::to_string(nv) + " vertices)");
    }
  }
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  formats::write_file_atomically(path, bytes);
}

// STL is little-endian whatever the host is.
void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}
void put_f32(std::string& s, double v) { put_u32(s, std::bit_cast<std::uint32_t>(static_cast<float>(v))); }

void put_number(std::string& s, double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);  // shortest round-trip
  s.append(buf.data(), r.ptr);
}

}  // namespace

TriMesh make_box_mesh(const Eigen::Vector3d& extents) {
  require(positive(extents.x()) && positive(extents.y()) && positive(extents.z()), "make_box_mesh",
          "extents must be finite and positive");
  TriMesh m;
  m.vertices.resize(8, 3);
  // Vertex i has x from bit 0, y from bit 1, z from bit 2 (0: negative side).
  for (int i = 0; i < 8; ++i) {
    m.vertices.row(i) << ((i & 1) ? 0.5 : -0.5) * extents.x(), ((i & 2) ? 0.5 : -0.5) * extents.y(),
        ((i & 4) ? 0.5 : -0.5) * extents.z();
  }
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 3, 0, 3, 1,  // -z
      4, 5, 7, 4, 7, 6,             // +z
      0, 1, 5, 0, 5, 4,             // -y
      2, 6, 7, 2, 7, 3,             // +y
      0, 4, 6, 0, 6, 2,             // -x
      1, 3, 7, 1, 7, 5;             // +x
  return m;
}

TriMesh make_cylinder_mesh(double radius, double height, int segments) {
  require(positive(radius) && positive(height), "make_cylinder_mesh", "radius and height must be finite and positive");
  require(segments >= 3 && segments <= kMaxSegments, "make_cylinder_mesh",
          "segments must be in [3, " + std::to_string(kMaxSegments) + "], got " + std::to_string(segments));
  return revolve({{radius, 0.0}, {radius, height}}, segments);
}

TriMesh make_bottle_mesh(const BottleShape& s) {
  require(positive(s.body_radius) && positive(s.body_height) && positive(s.cap_radius) && positive(s.cap_height),
          "make_bottle_mesh", "radii and heights must be finite and positive");
  require(std::isfinite(s.shoulder_height) && s.shoulder_height >= 0, "make_bottle_mesh",
          "shoulder_height must be finite and >= 0");
  require(s.cap_radius < s.body_radius, "make_bottle_mesh", "cap_radius must be smaller than body_radius");
  require(s.segments >= 3 && s.segments <= kMaxSegments, "make_bottle_mesh",
          "segments must be in [3, " + std::to_string(kMaxSegments) + "], got " + std::to_string(s.segments));
  const double z_body = s.body_height;
  const double z_shoulder = z_body + s.shoulder_height;
  return revolve({{s.body_radius, 0.0},
                  {s.body_radius, z_body},
                  {s.cap_radius, z_shoulder},
                  {s.cap_radius, z_shoulder + s.cap_height}},
                 s.segments);
}

TriMesh make_eraser_mesh() { return make_box_mesh(Eigen::Vector3d(0.13, 0.05, 0.035)); }

void write_stl_binary(const TriMesh& mesh, const std::filesystem::path& path) {
  check_indices(mesh, path);
  if (static_cast<std::uint64_t>(mesh.triangles.rows()) > std::numeric_limits<std::uint32_t>::max())
    throw Error(path.string(), "", "too many triangles for STL");
  std::string bytes;
  bytes.reserve(84 + 50 * static_cast<std::size_t>(mesh.triangles.rows()));
  // The header must not start with "solid", or readers take the file for ASCII STL.
  std::string header = "binary STL written by dmgplace";
  header.resize(80, ' ');
  bytes += header;
  put_u32(bytes, static_cast<std::uint32_t>(mesh.triangles.rows()));
  for (Eigen::Index i = 0; i < mesh.triangles.rows(); ++i) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(i, 0)).transpose();
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(i, 1)).transpose();
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(i, 2)).transpose();
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double len = cross.norm();
    const Eigen::Vector3d n = len > 0 ? Eigen::Vector3d(cross / len) : Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d* p : {&n, &a, &b, &c})
      for (int k = 0; k < 3; ++k) put_f32(bytes, (*p)[k]);
    bytes.append(2, '\0');  // attribute byte count
  }
  write_file(path, bytes);
}

void write_obj(const TriMesh& mesh, const std::filesystem::path& path) {
  check_indices(mesh, path);
  std::string text = "# written by dmgplace\n";
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    text += 'v';
    for (int k = 0; k < 3; ++k) {
      text += ' ';
      put_number(text, mesh.vertices(i, k));
    }
    text += '\n';
  }
  for (Eigen::Index i = 0; i < mesh.triangles.rows(); ++i) {
    text += 'f';
    for (int k = 0; k < 3; ++k) text += ' ' + std::to_string(mesh.triangles(i, k) + 1);
    text += '\n';
  }
  write_file(path, text);
}

}  // namespace dmgplace::tools
