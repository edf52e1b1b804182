#include "dmgplace/tools/geometry/convex_hull.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <map>
#include <vector>

#include "dmgplace/formats/shape_table.hpp"

namespace dmgplace::tools {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
}  // namespace

RowMatrixX3i convex_hull_triangles(const TriMesh& mesh) {
  std::vector<Point> points;
  std::map<Point, int> index;  // a hull vertex is an input point, exactly: back to its first row
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) {
    const Point p(mesh.vertices(i, 0), mesh.vertices(i, 1), mesh.vertices(i, 2));
    if (index.emplace(p, int(i)).second) points.push_back(p);
  }
  if (points.size() < 4) return {};
  // Flat or collinear input gives a polygon or a segment, not a closed surface: checked below.
  CGAL::Surface_mesh<Point> hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  if (hull.number_of_faces() < 4) return {};
  RowMatrixX3i out(long(hull.number_of_faces()), 3);
  long f = 0;
  for (auto face : hull.faces()) {
    int k = 0;
    for (auto v : CGAL::vertices_around_face(hull.halfedge(face), hull)) {
      if (k == 3) return {};  // convex_hull_3 triangulates: anything else is not a hull
      out(f, k++) = index.at(hull.point(v));
    }
    if (k != 3) return {};
    ++f;
  }
  // The artifact check, here too: a hull the loader would refuse is no hull.
  if (formats::hull_problem(mesh, out)) return {};
  return out;
}

}  // namespace dmgplace::tools
