#pragma once
// Built-in object meshes made by code (no mesh files in the repository), and plain mesh writers.
// Every mesh is closed, 2-manifold and consistently oriented (counter-clockwise seen from
// outside), without duplicate vertices or zero-area triangles. Units are metres.
#include <Eigen/Core>
#include <filesystem>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

// A glue-bottle-like solid of revolution about z, standing on z = 0: a body cylinder, a conical
// shoulder narrowing to the cap radius, and the cap cylinder on top.
struct BottleShape {
  double body_radius = 0.03;
  double body_height = 0.12;
  double shoulder_height = 0.02;  // may be 0 (a flat step from body to cap)
  double cap_radius = 0.012;      // must be smaller than body_radius
  double cap_height = 0.025;
  int segments = 32;  // vertices per ring, at least 3
};

// Axis-aligned box centered at the origin with full edge lengths `extents` (12 triangles).
TriMesh make_box_mesh(const Eigen::Vector3d& extents);

// Cylinder along z, base at z = 0, top at z = height, both ends capped. The cross-section is a
// regular polygon with `segments` vertices on the circle of `radius`.
TriMesh make_cylinder_mesh(double radius, double height, int segments);

TriMesh make_bottle_mesh(const BottleShape& shape = {});

// A board eraser: a 0.13 x 0.05 x 0.035 m box centered at the origin (long side along x).
TriMesh make_eraser_mesh();

// Binary STL (little-endian, float32). Throws dmgplace::Error naming `path` when the mesh has
// out-of-range indices or the file cannot be written.
void write_stl_binary(const TriMesh& mesh, const std::filesystem::path& path);

// Wavefront OBJ with `v` and `f` lines only (1-based indices), shortest round-trip decimals.
// Same errors as write_stl_binary.
void write_obj(const TriMesh& mesh, const std::filesystem::path& path);

}  // namespace dmgplace::tools
