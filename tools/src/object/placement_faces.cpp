#include "dmgplace/tools/object/placement_faces.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Hull = CGAL::Surface_mesh<K::Point_3>;

Eigen::Vector3d eig(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }

struct HullFacet {
  Eigen::Vector3d normal;
  double area = 0;
  std::vector<int> vertices, neighbours;
};

std::vector<HullFacet> hull_facets(const Hull& hull) {
  std::vector<HullFacet> out(hull.number_of_faces());
  for (auto f : hull.faces()) {
    HullFacet& h = out[f.idx()];
    std::vector<Eigen::Vector3d> pts;
    for (auto he : CGAL::halfedges_around_face(hull.halfedge(f), hull)) {
      auto v = hull.target(he);
      h.vertices.push_back(int(v.idx()));
      pts.push_back(eig(hull.point(v)));
      h.neighbours.push_back(int(hull.face(hull.opposite(he)).idx()));
    }
    Eigen::Vector3d n = Eigen::Vector3d::Zero();  // Newell: robust for any polygon
    for (std::size_t i = 0; i < pts.size(); ++i) n += pts[i].cross(pts[(i + 1) % pts.size()]);
    h.area = 0.5 * n.norm();
    h.normal = n.normalized();
  }
  return out;
}

// Andrew's monotone chain; returns indices of the hull CCW in the (x, y) plane.
std::vector<int> convex_hull_2d(const std::vector<Eigen::Vector2d>& p) {
  std::vector<int> idx(p.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return p[a].x() < p[b].x() || (p[a].x() == p[b].x() && p[a].y() < p[b].y()); });
  auto cross = [&](int o, int a, int b) {
    return (p[a] - p[o]).x() * (p[b] - p[o]).y() - (p[a] - p[o]).y() * (p[b] - p[o]).x();
  };
  std::vector<int> h(2 * idx.size());
  std::size_t k = 0;
  for (int i : idx) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], i) <= 0) --k;
    h[k++] = i;
  }
  for (std::size_t j = idx.size() - 1, t = k + 1; j-- > 0;) {
    const int i = idx[j];
    while (k >= t && cross(h[k - 2], h[k - 1], i) <= 0) --k;
    h[k++] = i;
  }
  h.resize(k > 1 ? k - 1 : k);
  return h;
}

double inside_distance(const std::vector<Eigen::Vector3d>& poly, const Eigen::Vector3d& n, const Eigen::Vector3d& q) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector3d e = poly[(i + 1) % poly.size()] - poly[i];
    if (e.norm() > 0) d = std::min(d, n.dot(e.cross(q - poly[i])) / e.norm());
  }
  return d;
}

}  // namespace

formats::PlacementFaces compute_placement_faces(const TriMesh& mesh, const Eigen::Vector3d& com,
                                                const PlacementOptions& o, const std::string& file) {
  if (!(o.merge_angle >= 0 && o.merge_angle < M_PI / 2) || !(o.margin >= 0) || !(o.margin_fraction >= 0))
    throw Error(file, "placement", "merge angle must be in [0, pi/2) and margins non-negative");
  std::vector<K::Point_3> points;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    points.emplace_back(mesh.vertices(i, 0), mesh.vertices(i, 1), mesh.vertices(i, 2));
  Hull hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  if (hull.number_of_faces() < 4) throw Error(file, "placement", "the mesh is flat: no 3-D convex hull");
  const auto facets = hull_facets(hull);

  // Region growing, largest facets first, against the seed facet's normal: a finely tessellated
  // curve does not chain into one face as it would with pairwise merging, and the region grows
  // symmetrically about its seed.
  std::vector<int> order(facets.size()), region(facets.size(), -1);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return facets[a].area > facets[b].area; });
  std::vector<std::vector<int>> regions;
  const double cos_merge = std::cos(o.merge_angle);
  for (int seed : order) {
    if (region[seed] >= 0) continue;
    const int r = int(regions.size());
    regions.push_back({seed});
    region[seed] = r;
    for (std::size_t q = 0; q < regions[r].size(); ++q)
      for (int nb : facets[regions[r][q]].neighbours) {
        if (region[nb] >= 0 || facets[nb].normal.dot(facets[seed].normal) < cos_merge) continue;
        region[nb] = r;
        regions[r].push_back(nb);
      }
  }

  // One candidate face per region; the required margin shrinks for thin objects.
  struct Candidate { Eigen::Vector3d n; double support, width; std::vector<int> verts; };
  std::vector<Candidate> cands;
  double min_width = std::numeric_limits<double>::infinity();
  for (const auto& reg : regions) {
    Candidate c;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int f : reg) {
      sum += facets[f].normal * facets[f].area;
      c.verts.insert(c.verts.end(), facets[f].vertices.begin(), facets[f].vertices.end());
    }
    if (sum.norm() == 0) continue;
    c.n = sum.normalized();
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
      const double d = c.n.dot(mesh.vertices.row(v).transpose());
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    c.support = hi;
    c.width = hi - lo;
    min_width = std::min(min_width, c.width);
    cands.push_back(std::move(c));
  }
  formats::PlacementFaces out;
  out.merge_angle = o.merge_angle;
  out.required_margin = std::min(o.margin, o.margin_fraction * min_width);
  for (const auto& c : cands) {
    const Eigen::Vector3d u = c.n.unitOrthogonal(), w = c.n.cross(u);  // u x w = n: CCW about n
    std::vector<Eigen::Vector2d> flat;
    for (int v : c.verts) {
      const Eigen::Vector3d p = eig(hull.point(Hull::Vertex_index(v)));
      flat.emplace_back(u.dot(p), w.dot(p));
    }
    const auto ring = convex_hull_2d(flat);
    if (ring.size() < 3) continue;
    formats::PlacementFace face;
    face.normal = c.n;
    for (int i : ring) face.polygon.push_back(flat[i].x() * u + flat[i].y() * w + c.support * c.n);
    face.margin = inside_distance(face.polygon, c.n, com);
    if (face.margin < out.required_margin) continue;
    face.rotation = Eigen::Quaterniond::FromTwoVectors(c.n, Eigen::Vector3d(0, 0, -1)).normalized();
    face.height = c.support;
    out.faces.push_back(std::move(face));
  }
  return out;
}

}  // namespace dmgplace::tools
