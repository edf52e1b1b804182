#include "dmgplace/tools/object/placement_faces.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <queue>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Hull = CGAL::Surface_mesh<K::Point_3>;

Eigen::Vector3d eig(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }

struct HullFacet {
  Eigen::Vector3d normal, centroid;
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
    // Start the cycle at its lexicographically smallest point: the sums below then do not depend
    // on which halfedge CGAL calls the face's first.
    const auto first =
        std::min_element(pts.begin(), pts.end(),
                         [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
                           return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
                         }) -
        pts.begin();
    std::rotate(pts.begin(), pts.begin() + first, pts.end());
    Eigen::Vector3d n = Eigen::Vector3d::Zero();  // Newell: robust for any polygon
    for (std::size_t i = 0; i < pts.size(); ++i) n += pts[i].cross(pts[(i + 1) % pts.size()]);
    h.area = 0.5 * n.norm();
    h.centroid = Eigen::Vector3d::Zero();
    for (const auto& p : pts) h.centroid += p / double(pts.size());
    h.normal = n.normalized();
  }
  return out;
}

// Andrew's monotone chain; returns indices of the hull CCW in the (x, y) plane.
std::vector<int> convex_hull_2d(const std::vector<Eigen::Vector2d>& p) {
  std::vector<int> idx(p.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(),
            [&](int a, int b) { return p[a].x() < p[b].x() || (p[a].x() == p[b].x() && p[a].y() < p[b].y()); });
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

// The rotation taking unit n to -z. Eigen's FromTwoVectors solves the antiparallel case (a face
// pointing up, n = +z) with an SVD whose choice among the equally good axes changed with memory
// alignment: the same mesh baked to different face frames. Here that case is a half turn about
// the x axis made perpendicular to n, the same every time.
Eigen::Quaterniond rotation_to_down(const Eigen::Vector3d& n) {
  const Eigen::Vector3d down(0, 0, -1);
  if (n.dot(down) > -1 + 1e-6) return Eigen::Quaterniond::FromTwoVectors(n, down).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  return Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, (x - x.dot(n) * n).normalized()));
}

// A key of each facet's geometry alone (normal, centroid), rounded so that last-bit noise cannot
// reorder it: CGAL numbers the hull's facets in an order that follows heap addresses (it changed
// with the length of the input's path), and the same mesh must always give the same faces.
using FacetKey = std::array<long long, 6>;
long long quantise(double v, double unit) { return std::llround(v / unit); }

std::vector<FacetKey> facet_keys(const std::vector<HullFacet>& facets) {
  std::vector<FacetKey> keys(facets.size());
  for (std::size_t f = 0; f < facets.size(); ++f) {
    const Eigen::Vector3d& n = facets[f].normal;
    const Eigen::Vector3d& c = facets[f].centroid;
    keys[f] = {quantise(n.x(), 1e-9), quantise(n.y(), 1e-9), quantise(n.z(), 1e-9),
               quantise(c.x(), 1e-9), quantise(c.y(), 1e-9), quantise(c.z(), 1e-9)};
  }
  return keys;
}

// Region growing against the seed facet's normal (a finely tessellated curve does not chain into
// one face as it would with pairwise merging, and a region grows symmetrically about its seed).
// Greedy: the seed whose region would have the largest area goes first, so a fan-triangulated
// disk becomes one face and a polygonal cylinder's sides are cut into the widest strips. Ties (a
// symmetric mesh has many) are broken by the facets' keys.
std::vector<std::vector<int>> grow_regions(const std::vector<HullFacet>& facets, const std::vector<FacetKey>& keys,
                                           double merge_angle) {
  double max_area = 0;
  for (const auto& f : facets) max_area = std::max(max_area, f.area);
  const double area_unit = max_area * 1e-9 + 1e-300;
  const double cos_merge = std::cos(merge_angle);
  std::vector<int> region(facets.size(), -1), mark(facets.size(), -1);
  // The unclaimed facets a region seeded at `seed` would take, and their area.
  const auto grow = [&](int seed, std::vector<int>& members) {
    members.assign(1, seed);
    mark[seed] = seed;
    double area = facets[seed].area;
    for (std::size_t k = 0; k < members.size(); ++k)
      for (int nb : facets[members[k]].neighbours) {
        if (region[nb] >= 0 || mark[nb] == seed || facets[nb].normal.dot(facets[seed].normal) < cos_merge) continue;
        mark[nb] = seed;
        members.push_back(nb);
        area += facets[nb].area;
      }
    for (int m : members) mark[m] = -1;
    return quantise(area, area_unit);
  };
  // Lazy greedy: claimed neighbours only shrink a region, so a stored area is an upper bound; a
  // popped seed whose recomputed area still equals its bound is the best one left.
  struct Entry {
    long long area;
    int facet;
  };
  const auto after = [&](const Entry& a, const Entry& b) {  // priority_queue puts the "largest" first
    return a.area != b.area ? a.area < b.area
                            : keys[b.facet] < keys[a.facet] || (keys[b.facet] == keys[a.facet] && b.facet < a.facet);
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(after)> queue(after);
  std::vector<int> members;
  for (int f = 0; f < int(facets.size()); ++f) queue.push({grow(f, members), f});
  std::vector<std::vector<int>> regions;
  while (!queue.empty()) {
    const Entry top = queue.top();
    queue.pop();
    if (region[top.facet] >= 0) continue;
    const long long area = grow(top.facet, members);
    if (area != top.area) {
      queue.push({area, top.facet});
      continue;
    }
    for (int m : members) region[m] = int(regions.size());
    regions.push_back(members);
  }
  return regions;
}

// One candidate face per region: its area-weighted normal, the mesh's support along it and its
// width across it.
struct Candidate {
  Eigen::Vector3d n;
  double support, width;
  std::vector<int> verts;
};

std::vector<Candidate> region_candidates(std::vector<std::vector<int>>& regions, const std::vector<HullFacet>& facets,
                                         const std::vector<FacetKey>& keys, const TriMesh& mesh) {
  std::vector<Candidate> cands;
  for (auto& reg : regions) {
    // Sum in the canonical order too: a floating-point sum depends on its order.
    std::sort(reg.begin(), reg.end(), [&](int a, int b) { return keys[a] < keys[b] || (keys[a] == keys[b] && a < b); });
    Candidate c;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int f : reg) {
      sum += facets[f].normal * facets[f].area;
      c.verts.insert(c.verts.end(), facets[f].vertices.begin(), facets[f].vertices.end());
    }
    if (sum.norm() == 0) continue;
    // CGAL may triangulate a coplanar hull face differently from run to run, so the sum varies in
    // its last bits (0 or -2.4e-16): snap it to a 2^-40 grid first, far below any geometric effect.
    const double length = sum.norm();
    for (int k = 0; k < 3; ++k)
      sum[k] = std::ldexp(std::round(std::ldexp(sum[k] / length, 40)), -40) + 0.0;  // + 0.0: no -0
    c.n = sum.normalized();
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
      const double d = c.n.dot(mesh.vertices.row(v).transpose());
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    c.support = hi;
    c.width = hi - lo;
    cands.push_back(std::move(c));
  }
  return cands;
}

// The candidate's face: the 2-D hull of its vertices in its plane, kept where the center of mass
// projects at least `required_margin` inside it.
std::optional<formats::PlacementFace> candidate_face(const Candidate& c, const Hull& hull, const Eigen::Vector3d& com,
                                                     double required_margin) {
  const Eigen::Vector3d u = c.n.unitOrthogonal(), w = c.n.cross(u);  // u x w = n: CCW about n
  std::vector<Eigen::Vector2d> flat;
  for (int v : c.verts) {
    const Eigen::Vector3d p = eig(hull.point(Hull::Vertex_index(v)));
    flat.emplace_back(u.dot(p), w.dot(p));
  }
  const auto ring = convex_hull_2d(flat);
  if (ring.size() < 3) return std::nullopt;
  formats::PlacementFace face;
  face.normal = c.n;
  for (int i : ring) face.polygon.push_back(flat[i].x() * u + flat[i].y() * w + c.support * c.n);
  face.margin = inside_distance(face.polygon, c.n, com);
  if (face.margin < required_margin) return std::nullopt;
  face.rotation = rotation_to_down(c.n);
  face.height = c.support;
  return face;
}

}  // namespace

formats::PlacementFaces compute_placement_faces(const TriMesh& mesh, const Eigen::Vector3d& com, const FaceOptions& o,
                                                const std::string& file) {
  if (!(o.merge_angle >= 0 && o.merge_angle < M_PI / 2) || !(o.margin >= 0) || !(o.margin_fraction >= 0))
    throw Error(file, "placement", "merge angle must be in [0, pi/2) and margins non-negative");
  std::vector<K::Point_3> points;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    points.emplace_back(mesh.vertices(i, 0), mesh.vertices(i, 1), mesh.vertices(i, 2));
  Hull hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  if (hull.number_of_faces() < 4) throw Error(file, "placement", "the mesh is flat: no 3-D convex hull");
  const auto facets = hull_facets(hull);
  const auto keys = facet_keys(facets);
  auto regions = grow_regions(facets, keys, o.merge_angle);
  const auto cands = region_candidates(regions, facets, keys, mesh);
  // The required margin shrinks for thin objects.
  double min_width = std::numeric_limits<double>::infinity();
  for (const auto& c : cands) min_width = std::min(min_width, c.width);
  formats::PlacementFaces out;
  out.merge_angle = o.merge_angle;
  out.required_margin = std::min(o.margin, o.margin_fraction * min_width);
  for (const auto& c : cands)
    if (auto face = candidate_face(c, hull, com, out.required_margin)) out.faces.push_back(std::move(*face));
  return out;
}

}  // namespace dmgplace::tools
