#pragma once
// Checks and cleans triangle meshes read from files: topology counts, degenerate and duplicate
// faces, duplicate vertices and face orientation.
#include <cstddef>
#include <string>
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

struct MeshReport {
  std::size_t boundary_edges = 0;      // undirected edges used by exactly one face
  std::size_t nonmanifold_edges = 0;   // undirected edges used by more than two faces
  std::size_t inconsistent_edges = 0;  // two-face edges both faces walk the same way (a directed
                                       // edge used twice); non-manifold edges only count as such
  std::size_t degenerate_faces = 0;    // zero area or a repeated vertex
  std::size_t duplicate_faces = 0;     // same three vertices as an earlier face
  std::size_t merged_vertices = 0;     // exact duplicate vertices folded together (clean_mesh)
  bool repaired_orientation = false;   // clean_mesh changed the winding of some faces
  std::vector<std::string> warnings;   // human-readable, one line each, without the file name

  bool closed_manifold() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
};

// Counts the defects of `mesh` as it is. A face is degenerate when it repeats a vertex or its
// area is <= degenerate_area * (bounding-box diagonal)^2. Out-of-range indices: dmgplace::Error.
MeshReport check_mesh(const TriMesh& mesh, double degenerate_area = 1e-12);

// Volume enclosed by the faces, positive when they face outwards (only meaningful when closed).
double signed_volume(const TriMesh& mesh);

// Validates and cleans `mesh`; `file` names the source in every dmgplace::Error.
// Rejects: no vertices or faces, non-finite vertices, out-of-range indices, more than 10% of the
// faces degenerate. Merges exactly equal vertices, drops degenerate and duplicate faces and
// unused vertices, and (when `repair`) re-orients inconsistent or inside-out faces with CGAL
// (closed meshes always go through it, which also turns an outward-facing cavity inwards).
// On return the edge counts of `report` describe the returned mesh, the other counts what was
// removed; open and non-manifold meshes and implausible sizes become warnings.
TriMesh clean_mesh(const TriMesh& mesh, const std::string& file, MeshReport& report, bool repair = true);

}  // namespace dmgplace::tools
