#pragma once
// The convex hull of a mesh's vertices (CGAL, exact predicates) as triangles over those vertices:
// what bake-robot stores beside each link mesh (Shape::hull) for the exact layer's gaps.
#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

// Outward triangles indexing mesh.vertices; empty when the vertices span no volume (flat or
// fewer than four points).
RowMatrixX3i convex_hull_triangles(const TriMesh& mesh);

}  // namespace dmgplace::tools
