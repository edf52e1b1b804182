#include "dmgplace/tools/geometry/convex_hull.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "dmgplace/formats/shape_table.hpp"

namespace dmgplace::tools {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;

// The hull's facets (its triangles merged across every edge whose two triangles are exactly
// coplanar), each as its corners in order: CGAL triangulates a flat facet however its internals
// happened to meet it, which varies with the addresses it allocated, and keeps points it met
// first that turn out to lie in a facet or on an edge.
std::vector<std::vector<int>> exact_facets(const CGAL::Surface_mesh<Point>& hull, const std::map<Point, int>& index) {
  using Mesh = CGAL::Surface_mesh<Point>;
  const std::size_t nf = hull.num_faces();  // the index range
  std::vector<std::size_t> root(nf);
  for (std::size_t f = 0; f < nf; ++f) root[f] = f;
  auto find = [&](std::size_t f) {
    while (root[f] != f) f = root[f] = root[root[f]];
    return f;
  };
  auto point = [&](Mesh::Halfedge_index h) { return hull.point(hull.target(h)); };
  for (auto h : hull.halfedges())
    if (hull.is_border(h)) return {};  // flat input: a polygon, not a closed surface
  for (auto e : hull.edges()) {
    const auto h = hull.halfedge(e), o = hull.opposite(h);
    if (CGAL::coplanar(point(h), point(hull.next(h)), point(o), point(hull.next(o))))
      root[find(hull.face(h).idx())] = find(hull.face(o).idx());
  }
  // Each facet's boundary: the halfedges whose other side is another facet, chained tip to tail.
  std::map<std::size_t, std::map<Mesh::Vertex_index, Mesh::Halfedge_index>> boundary;
  for (auto h : hull.halfedges()) {
    const std::size_t f = find(hull.face(h).idx());
    if (f != find(hull.face(hull.opposite(h)).idx())) boundary[f][hull.source(h)] = h;
  }
  std::vector<std::vector<int>> out;
  for (const auto& [f, from] : boundary) {
    std::vector<Point> ring;
    const auto first = from.begin()->second;
    auto h = first;
    do {
      ring.push_back(hull.point(hull.source(h)));
      const auto next = from.find(hull.target(h));
      if (next == from.end()) return {};
      h = next->second;
    } while (h != first && ring.size() <= from.size());
    if (h != first || ring.size() != from.size()) return {};  // not one cycle: not a convex facet
    // Points on a side between two corners go: a fan over them would have flat triangles.
    for (bool dropped = true; dropped && ring.size() > 3;) {
      dropped = false;
      for (std::size_t i = 0; i < ring.size() && ring.size() > 3; ++i) {
        const std::size_t a = (i + ring.size() - 1) % ring.size(), b = (i + 1) % ring.size();
        if (CGAL::collinear(ring[a], ring[i], ring[b])) ring.erase(ring.begin() + long(i)), dropped = true;
      }
    }
    std::vector<int> corners;
    for (const auto& p : ring) corners.push_back(index.at(p));
    out.push_back(std::move(corners));
  }
  return out;
}
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
  // Each facet fanned from its corner listed first in the mesh: the same triangles whatever
  // order CGAL met the points in; the triangles sorted, each from its smallest index.
  std::vector<std::array<int, 3>> tris;
  for (auto corners : exact_facets(hull, index)) {
    if (corners.size() < 3) return {};
    std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      std::array<int, 3> t{corners[0], corners[k], corners[k + 1]};
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      tris.push_back(t);
    }
  }
  std::sort(tris.begin(), tris.end());
  RowMatrixX3i out(long(tris.size()), 3);
  for (std::size_t f = 0; f < tris.size(); ++f)
    for (int k = 0; k < 3; ++k) out(long(f), k) = tris[f][std::size_t(k)];
  // The artifact check, here too: a hull the loader would refuse is no hull.
  if (formats::hull_problem(mesh, out)) return {};
  return out;
}

}  // namespace dmgplace::tools
