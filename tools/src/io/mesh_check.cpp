#include "dmgplace/tools/io/mesh_check.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <unordered_map>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Soup = std::vector<std::vector<std::size_t>>;

std::string num(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

std::uint64_t edge_key(int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }

double bbox_diagonal2(const RowMatrixX3d& v) {
  if (v.rows() == 0) return 0;
  return (v.colwise().maxCoeff() - v.colwise().minCoeff()).squaredNorm();
}

double face_area(const TriMesh& m, int f) {
  const Eigen::Vector3d a = m.vertices.row(m.triangles(f, 0)), b = m.vertices.row(m.triangles(f, 1)),
                        c = m.vertices.row(m.triangles(f, 2));
  return 0.5 * (b - a).cross(c - a).norm();
}

std::array<int, 3> sorted_face(const TriMesh& m, int f) {
  std::array<int, 3> k{m.triangles(f, 0), m.triangles(f, 1), m.triangles(f, 2)};
  std::sort(k.begin(), k.end());
  return k;
}

void check_indices(const TriMesh& m, const std::string& file) {
  const Eigen::Index n = m.vertices.rows();
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    for (int j = 0; j < 3; ++j)
      if (m.triangles(f, j) < 0 || m.triangles(f, j) >= n)
        throw Error(
            file, "triangle " + std::to_string(f),
            "vertex index " + std::to_string(m.triangles(f, j)) + " out of range [0, " + std::to_string(n) + ")");
}

// Exactly equal positions become one vertex; returns old -> new index.
std::vector<int> merge_duplicates(const RowMatrixX3d& v, RowMatrixX3d& out) {
  std::map<std::array<double, 3>, int> ids;
  std::vector<int> remap(std::size_t(v.rows()));
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    const auto [it, fresh] = ids.emplace(std::array<double, 3>{v(i, 0), v(i, 1), v(i, 2)}, int(keep.size()));
    if (fresh) keep.push_back(i);
    remap[std::size_t(i)] = it->second;
  }
  out.resize(Eigen::Index(keep.size()), 3);
  for (std::size_t i = 0; i < keep.size(); ++i) out.row(Eigen::Index(i)) = v.row(keep[i]);
  return remap;
}

// Keeps only the vertices the faces use, in first-use order.
TriMesh compact(const RowMatrixX3d& v, const std::vector<std::array<int, 3>>& faces) {
  std::vector<int> remap(std::size_t(v.rows()), -1);
  std::vector<int> order;
  TriMesh out;
  out.triangles.resize(Eigen::Index(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int j = 0; j < 3; ++j) {
      int& r = remap[std::size_t(faces[f][std::size_t(j)])];
      if (r < 0) {
        r = int(order.size());
        order.push_back(faces[f][std::size_t(j)]);
      }
      out.triangles(Eigen::Index(f), j) = r;
    }
  out.vertices.resize(Eigen::Index(order.size()), 3);
  for (std::size_t i = 0; i < order.size(); ++i) out.vertices.row(Eigen::Index(i)) = v.row(order[i]);
  return out;
}

// Signed volume of one piece, measured from the piece's centroid (an open piece has no
// reference-free volume; the centroid makes the sign a fair inside/outside guess).
double soup_volume(const std::vector<Point>& pts, const Soup& polys, const std::vector<std::size_t>& faces) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t f : faces)
    for (std::size_t v : polys[f]) c += Eigen::Vector3d(pts[v].x(), pts[v].y(), pts[v].z());
  c /= double(3 * faces.size());
  double vol = 0;
  for (std::size_t f : faces) {
    Eigen::Vector3d q[3];
    for (int j = 0; j < 3; ++j) {
      const Point& p = pts[polys[f][std::size_t(j)]];
      q[j] = Eigen::Vector3d(p.x(), p.y(), p.z()) - c;
    }
    vol += q[0].dot(q[1].cross(q[2]));
  }
  return vol / 6.0;
}

// Faces grouped into connected pieces (faces sharing a vertex).
std::vector<std::vector<std::size_t>> pieces(std::size_t num_points, const Soup& polys) {
  std::vector<std::size_t> parent(num_points);
  std::iota(parent.begin(), parent.end(), std::size_t(0));
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& p : polys) parent[find(p[1])] = find(p[0]), parent[find(p[2])] = find(p[0]);
  std::map<std::size_t, std::vector<std::size_t>> by_root;
  for (std::size_t f = 0; f < polys.size(); ++f) by_root[find(polys[f][0])].push_back(f);
  std::vector<std::vector<std::size_t>> out;
  for (auto& [root, faces] : by_root) out.push_back(std::move(faces));
  return out;
}

// Open meshes cannot be told inside from outside exactly: flip each connected piece whose signed
// volume is negative (a good guess for nearly closed scans with small holes).
void orient_open_pieces(const std::vector<Point>& pts, Soup& polys) {
  for (const auto& faces : pieces(pts.size(), polys))
    if (soup_volume(pts, polys, faces) < 0)
      for (std::size_t f : faces) std::swap(polys[f][1], polys[f][2]);
}

void to_soup(const TriMesh& m, std::vector<Point>& pts, Soup& polys) {
  pts.clear();
  pts.reserve(std::size_t(m.vertices.rows()));
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    pts.emplace_back(m.vertices(i, 0), m.vertices(i, 1), m.vertices(i, 2));
  polys.assign(std::size_t(m.triangles.rows()), {});
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    polys[std::size_t(f)] = {std::size_t(m.triangles(f, 0)), std::size_t(m.triangles(f, 1)),
                             std::size_t(m.triangles(f, 2))};
}

// True when some connected piece encloses a clearly negative volume (faces pointing inwards).
bool has_inside_out_piece(const TriMesh& m, double tolerance) {
  std::vector<Point> pts;
  Soup polys;
  to_soup(m, pts, polys);
  for (const auto& faces : pieces(pts.size(), polys))
    if (soup_volume(pts, polys, faces) < -tolerance) return true;
  return false;
}

// The faces as oriented triangles of positions, independent of vertex numbering and face order.
std::vector<std::array<double, 9>> oriented_faces(const TriMesh& m) {
  std::vector<std::array<double, 9>> out;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    std::array<std::array<double, 3>, 3> c;
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[std::size_t(j)][std::size_t(k)] = m.vertices(m.triangles(f, j), k);
    const auto first = std::size_t(std::min_element(c.begin(), c.end()) - c.begin());  // rotation keeps winding
    std::array<double, 9> key;
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t k = 0; k < 3; ++k) key[3 * j + k] = c[(first + j) % 3][k];
    out.push_back(key);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// CGAL re-orientation: consistent orientation per piece, then outward (bounding a volume).
TriMesh reorient(const TriMesh& m) {
  std::vector<Point> pts;
  Soup polys;
  to_soup(m, pts, polys);

  PMP::orient_polygon_soup(pts, polys);  // may duplicate points at non-manifold spots
  bool done = false;
  if (PMP::is_polygon_soup_a_polygon_mesh(polys)) {
    CGAL::Surface_mesh<Point> sm;
    PMP::polygon_soup_to_polygon_mesh(pts, polys, sm);
    if (CGAL::is_closed(sm)) {
      PMP::orient_to_bound_a_volume(sm);
      pts.assign(sm.points().begin(), sm.points().end());
      polys.clear();
      for (auto f : sm.faces()) {
        std::vector<std::size_t> poly;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) poly.push_back(std::size_t(v.idx()));
        polys.push_back(poly);
      }
      done = true;
    }
  }
  if (!done) orient_open_pieces(pts, polys);

  RowMatrixX3d v(Eigen::Index(pts.size()), 3);
  for (std::size_t i = 0; i < pts.size(); ++i) v.row(Eigen::Index(i)) << pts[i].x(), pts[i].y(), pts[i].z();
  // Fold the points orient_polygon_soup duplicated back together.
  RowMatrixX3d merged;
  const std::vector<int> remap = merge_duplicates(v, merged);
  std::vector<std::array<int, 3>> faces;
  for (const auto& p : polys) faces.push_back({remap[p[0]], remap[p[1]], remap[p[2]]});
  return compact(merged, faces);
}

}  // namespace

MeshReport check_mesh(const TriMesh& m, double degenerate_area) {
  check_indices(m, "");
  MeshReport r;
  const double tol = degenerate_area * bbox_diagonal2(m.vertices);
  std::unordered_map<std::uint64_t, int> undirected, directed;
  std::set<std::array<int, 3>> seen;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const auto key = sorted_face(m, int(f));
    const bool repeated = key[0] == key[1] || key[1] == key[2];
    if (repeated || face_area(m, int(f)) <= tol) ++r.degenerate_faces;
    if (!seen.insert(key).second) ++r.duplicate_faces;
    if (repeated) continue;
    for (int j = 0; j < 3; ++j) {
      const int a = m.triangles(f, j), b = m.triangles(f, (j + 1) % 3);
      ++directed[edge_key(a, b)];
      ++undirected[edge_key(std::min(a, b), std::max(a, b))];
    }
  }
  for (const auto& [k, n] : undirected) {
    if (n == 1) ++r.boundary_edges;
    if (n > 2) ++r.nonmanifold_edges;
    // Two faces agree when each walks the edge once, one each way (k is the min->max direction).
    if (n == 2 && directed[k] != 1) ++r.inconsistent_edges;
  }
  return r;
}

double signed_volume(const TriMesh& m) {
  if (m.empty()) return 0;
  const Eigen::RowVector3d c = m.vertices.colwise().mean();  // centring keeps the sum accurate
  double vol = 0;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(f, 0)) - c, b = m.vertices.row(m.triangles(f, 1)) - c,
                          d = m.vertices.row(m.triangles(f, 2)) - c;
    vol += a.dot(b.cross(d));
  }
  return vol / 6.0;
}

namespace {

// Duplicate vertices merged, degenerate and duplicate faces dropped (a duplicate with either
// winding is one face), counted in `report`.
TriMesh merge_and_drop_faces(const TriMesh& in, const std::string& file, MeshReport& report) {
  TriMesh merged;
  const std::vector<int> remap = merge_duplicates(in.vertices, merged.vertices);
  report.merged_vertices = std::size_t(in.vertices.rows() - merged.vertices.rows());
  merged.triangles.resize(in.triangles.rows(), 3);
  for (Eigen::Index f = 0; f < in.triangles.rows(); ++f)
    for (int j = 0; j < 3; ++j) merged.triangles(f, j) = remap[std::size_t(in.triangles(f, j))];
  const double tol = 1e-12 * bbox_diagonal2(merged.vertices);
  std::set<std::array<int, 3>> seen;
  std::vector<std::array<int, 3>> faces;
  for (Eigen::Index f = 0; f < merged.triangles.rows(); ++f) {
    const auto key = sorted_face(merged, int(f));
    if (key[0] == key[1] || key[1] == key[2] || face_area(merged, int(f)) <= tol) {
      ++report.degenerate_faces;
    } else if (!seen.insert(key).second) {
      ++report.duplicate_faces;
    } else {
      faces.push_back({merged.triangles(f, 0), merged.triangles(f, 1), merged.triangles(f, 2)});
    }
  }
  const std::size_t total = std::size_t(in.triangles.rows());
  if (report.degenerate_faces * 10 > total)
    throw Error(file, "triangles",
                std::to_string(report.degenerate_faces) + " of " + std::to_string(total) +
                    " faces are degenerate (zero area); more than 10% means the file is broken");
  if (report.degenerate_faces)
    report.warnings.push_back("dropped " + std::to_string(report.degenerate_faces) + " degenerate faces");
  if (report.duplicate_faces)
    report.warnings.push_back("dropped " + std::to_string(report.duplicate_faces) + " duplicate faces");
  return compact(merged.vertices, faces);
}

// Faces turned consistently outward where they are not (or, with `repair`, wherever CGAL turns
// a closed mesh); the edge report of the result.
MeshReport orient_outward(TriMesh& out, const std::string& file, MeshReport& report, bool repair) {
  MeshReport edges = check_mesh(out);
  const double diag = std::sqrt(bbox_diagonal2(out.vertices));
  // Per piece, so one inside-out body next to a good one is caught; the tolerance ignores the
  // rounding noise of flat pieces.
  const bool inside_out = has_inside_out_piece(out, 1e-9 * diag * diag * diag);
  const bool suspect = edges.inconsistent_edges > 0 || inside_out;
  // A closed mesh is always run through CGAL: it alone sees a cavity whose faces point outwards.
  if (!suspect && !(repair && edges.closed_manifold())) return edges;
  const std::string why = edges.inconsistent_edges > 0
                              ? std::to_string(edges.inconsistent_edges) + " edges with inconsistent orientation"
                          : inside_out ? "faces point inwards (signed volume " + num(signed_volume(out)) + " m^3)"
                                       : "a shell was turned inside out";
  if (!repair) {
    report.warnings.push_back(why + " (not repaired)");
    return edges;
  }
  TriMesh fixed;
  try {
    fixed = reorient(out);
  } catch (const std::exception& e) {  // CGAL preconditions throw when enabled
    throw Error(file, "mesh", "orientation repair failed: " + std::string(e.what()));
  }
  // A hollow body's inner shell rightly points inwards: only a changed winding is a repair.
  if (oriented_faces(fixed) != oriented_faces(out)) {
    report.repaired_orientation = true;
    report.warnings.push_back("repaired orientation: " + why);
  }
  out = std::move(fixed);
  return check_mesh(out);
}

}  // namespace

TriMesh clean_mesh(const TriMesh& in, const std::string& file, MeshReport& report, bool repair) {
  report = MeshReport{};
  if (in.vertices.rows() == 0) throw Error(file, "mesh", "no vertices");
  if (in.triangles.rows() == 0) throw Error(file, "mesh", "no triangles");
  for (Eigen::Index i = 0; i < in.vertices.rows(); ++i)
    if (!in.vertices.row(i).allFinite())
      throw Error(file, "vertex " + std::to_string(i), "coordinate is NaN or infinite");
  check_indices(in, file);

  TriMesh out = merge_and_drop_faces(in, file, report);
  const MeshReport edges = orient_outward(out, file, report, repair);
  report.boundary_edges = edges.boundary_edges;
  report.nonmanifold_edges = edges.nonmanifold_edges;
  report.inconsistent_edges = edges.inconsistent_edges;
  if (edges.boundary_edges)
    report.warnings.push_back("open mesh: " + std::to_string(edges.boundary_edges) + " boundary edges");
  if (edges.nonmanifold_edges)
    report.warnings.push_back("non-manifold mesh: " + std::to_string(edges.nonmanifold_edges) +
                              " edges shared by more than two faces");
  if (edges.inconsistent_edges)
    report.warnings.push_back(std::to_string(edges.inconsistent_edges) + " edges still inconsistently oriented");

  const double diag = std::sqrt(bbox_diagonal2(out.vertices));
  if (diag > 5.0)
    report.warnings.push_back("bounding-box diagonal " + num(diag) +
                              " m is implausibly large for an object (millimetres? use --scale 0.001)");
  else if (diag < 0.005)
    report.warnings.push_back("bounding-box diagonal " + num(diag) + " m is below 5 mm (wrong unit? check --scale)");
  return out;
}

}  // namespace dmgplace::tools
