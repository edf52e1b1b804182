#include "dmgplace/tools/scan/surface_reconstruction.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/convex_hull_3.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/poisson.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <numeric>

#include "../object/dmg_internal.hpp"
#include "scan_smoothing.hpp"
#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;

constexpr double kMinShellFraction = 0.25;  // a Poisson solid holds at least this share of the points' hull

TriMesh to_trimesh(const Mesh& sm) {
  TriMesh out;
  std::map<Mesh::Vertex_index, int> index;
  out.vertices.resize(Eigen::Index(sm.number_of_vertices()), 3);
  for (auto x : sm.vertices()) {
    const int i = int(index.size());
    index[x] = i;
    const auto& p = sm.point(x);
    out.vertices.row(i) << p.x(), p.y(), p.z();
  }
  out.triangles.resize(Eigen::Index(sm.number_of_faces()), 3);
  Eigen::Index t = 0;
  for (auto f : sm.faces()) {
    int c = 0;
    for (auto x : CGAL::vertices_around_face(sm.halfedge(f), sm)) out.triangles(t, c++) = index.at(x);
    ++t;
  }
  return out;
}

// Vertices sorted lexicographically, each face rotated to start at its smallest index, faces
// sorted: CGAL and PCL number their outputs in orders that need not repeat across runs.
TriMesh canonical(const TriMesh& m) {
  std::vector<int> order(std::size_t(m.vertices.rows()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    for (int c = 0; c < 3; ++c)
      if (m.vertices(a, c) != m.vertices(b, c)) return m.vertices(a, c) < m.vertices(b, c);
    return a < b;
  });
  std::vector<int> new_index(order.size());
  TriMesh out;
  out.vertices.resize(m.vertices.rows(), 3);
  for (std::size_t i = 0; i < order.size(); ++i) {
    new_index[std::size_t(order[i])] = int(i);
    out.vertices.row(Eigen::Index(i)) = m.vertices.row(order[i]);
  }
  std::vector<std::array<int, 3>> faces;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    std::array<int, 3> f{new_index[std::size_t(m.triangles(t, 0))], new_index[std::size_t(m.triangles(t, 1))],
                         new_index[std::size_t(m.triangles(t, 2))]};
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    faces.push_back(f);
  }
  std::sort(faces.begin(), faces.end());
  out.triangles.resize(Eigen::Index(faces.size()), 3);
  for (std::size_t t = 0; t < faces.size(); ++t)
    out.triangles.row(Eigen::Index(t)) << faces[t][0], faces[t][1], faces[t][2];
  return out;
}

TriMesh hull_of(const std::vector<Eigen::Vector3d>& points) {
  std::vector<K::Point_3> pts;
  for (const auto& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  Mesh hull;
  CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
  return to_trimesh(hull);
}

TriMesh poisson_of(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                   const ReconstructOptions& o) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    pcl::PointNormal p;
    p.x = float(points[i].x()), p.y = float(points[i].y()), p.z = float(points[i].z());
    p.normal_x = float(normals[i].x()), p.normal_y = float(normals[i].y()), p.normal_z = float(normals[i].z());
    cloud->push_back(p);
  }
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(o.poisson_depth);
  poisson.setSamplesPerNode(float(o.poisson_samples_per_node));
  poisson.setManifold(true);
  poisson.setOutputPolygons(false);
  poisson.setInputCloud(cloud);
  pcl::PointCloud<pcl::PointNormal> vertices;
  std::vector<pcl::Vertices> polygons;
  poisson.reconstruct(vertices, polygons);
  TriMesh m;
  m.vertices.resize(Eigen::Index(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    m.vertices.row(Eigen::Index(i)) << vertices[i].x, vertices[i].y, vertices[i].z;
  std::vector<std::array<int, 3>> tris;
  for (const auto& poly : polygons)
    for (std::size_t k = 1; k + 1 < poly.vertices.size(); ++k)
      tris.push_back({int(poly.vertices[0]), int(poly.vertices[k]), int(poly.vertices[k + 1])});
  m.triangles.resize(Eigen::Index(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t) m.triangles.row(Eigen::Index(t)) << tris[t][0], tris[t][1], tris[t][2];
  return m;
}

// PCL's Poisson leaves small holes where its octree's marching cubes meet; each border loop is
// closed by a minimal-area triangulation (CGAL).
TriMesh fill_holes(const TriMesh& m, std::size_t& filled) {
  Mesh sm;
  std::vector<Mesh::Vertex_index> v;
  for (Eigen::Index i = 0; i < m.vertices.rows(); ++i)
    v.push_back(sm.add_vertex(K::Point_3(m.vertices(i, 0), m.vertices(i, 1), m.vertices(i, 2))));
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t)
    sm.add_face(v[std::size_t(m.triangles(t, 0))], v[std::size_t(m.triangles(t, 1))],
                v[std::size_t(m.triangles(t, 2))]);
  CGAL::Polygon_mesh_processing::stitch_borders(sm);  // cracks first: borders that meet are sewn
  std::vector<Mesh::Halfedge_index> borders;
  CGAL::Polygon_mesh_processing::extract_boundary_cycles(sm, std::back_inserter(borders));
  for (auto h : borders) {
    std::vector<Mesh::Face_index> faces;
    CGAL::Polygon_mesh_processing::triangulate_hole(sm, h, std::back_inserter(faces));
    filled += !faces.empty();
  }
  // A slit (a hole whose corners are collinear) is filled with zero-area triangles, which the
  // cleaning would drop again: collapse them here, keeping the surface closed.
  CGAL::Polygon_mesh_processing::remove_degenerate_faces(sm);
  sm.collect_garbage();
  // The cleaning oriented only closed meshes; this one has just been closed.
  if (CGAL::is_closed(sm)) CGAL::Polygon_mesh_processing::orient_to_bound_a_volume(sm);
  return to_trimesh(sm);
}

}  // namespace

double seen_fraction(const TriMesh& mesh, const std::vector<Eigen::Vector3d>& points, double distance) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i) box.extend(mesh.vertices.row(i).transpose());
  // About 20k samples over the surface, but never coarser than the distance itself.
  double area = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
    area += 0.5 * (mesh.vertices.row(mesh.triangles(t, 1)).transpose() - a)
                      .cross(mesh.vertices.row(mesh.triangles(t, 2)).transpose() - a)
                      .norm();
  }
  if (!(area > 0) || points.empty()) return 0;
  const double spacing = std::min(distance, std::sqrt(area / 20000));
  const auto samples = detail::sample_surface(mesh, spacing);
  const detail::SampleGrid grid(points, distance);
  std::size_t seen = 0;
  for (const auto& p : samples.position) seen += grid.nearest(p, distance) >= 0;
  return samples.position.empty() ? 0 : double(seen) / double(samples.position.size());
}

TriMesh reconstruct_surface(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                            const ReconstructOptions& o, const std::string& file, ReconstructionReport& report) {
  if (points.size() < 4 || normals.size() != points.size())
    throw Error(file, "reconstruction", "needs at least 4 points, each with a normal");
  if (o.poisson_depth < 4 || o.poisson_depth > 12 || !(o.poisson_samples_per_node >= 1) || !(o.seen_distance >= 0))
    throw Error(file, "reconstruction", "Poisson depth must be in [4, 12], samples per node >= 1, seen distance >= 0");
  report = {};
  report.point_spacing = detail::median_point_spacing(points);
  report.seen_distance = o.seen_distance > 0 ? o.seen_distance : std::max(3 * report.point_spacing, 1e-4);
  const TriMesh raw = o.method == Reconstruction::Hull ? hull_of(points) : poisson_of(points, normals, o);
  if (raw.triangles.rows() < 4)
    throw Error(file, "reconstruction",
                std::string(o.method == Reconstruction::Hull ? "the convex hull" : "Poisson") +
                    " gave no surface (are the points flat?)");
  // Holes are filled after the cleaning, and the result is not cleaned again: a fill triangle of
  // near-zero area across a slit closes the surface, and dropping it would reopen the slit.
  std::size_t holes = 0;
  TriMesh mesh = canonical(clean_mesh(canonical(raw), file, report.mesh));
  for (int round = 0; round < 3 && report.mesh.boundary_edges > 0 && report.mesh.nonmanifold_edges == 0; ++round) {
    mesh = canonical(fill_holes(mesh, holes));
    const MeshReport filled = check_mesh(mesh);
    report.mesh.boundary_edges = filled.boundary_edges;
    report.mesh.nonmanifold_edges = filled.nonmanifold_edges;
    report.mesh.inconsistent_edges = filled.inconsistent_edges;
  }
  if (holes > 0)
    report.warnings.push_back("filled " + std::to_string(holes) + " small holes the surface was left with");
  if (!report.mesh.closed_manifold())
    throw Error(file, "reconstruction",
                "the surface is not closed (" + std::to_string(report.mesh.boundary_edges) + " boundary, " +
                    std::to_string(report.mesh.nonmanifold_edges) +
                    " non-manifold edges): try --reconstruct hull or another --poisson-depth");
  // A view of one side gives Poisson a thin shell around the seen surface, not a solid.
  const double volume = signed_volume(mesh), hull_volume = signed_volume(hull_of(points));
  if (o.method == Reconstruction::Poisson && !(volume > kMinShellFraction * hull_volume)) {
    char b[240];
    std::snprintf(b, sizeof b,
                  "Poisson gave a thin shell around the seen surface (%.3g m^3 against %.3g m^3 in the points' hull): "
                  "the scans show too little of the object; use --reconstruct hull, or scan more sides",
                  volume, hull_volume);
    throw Error(file, "reconstruction", b);
  }
  report.seen_fraction = seen_fraction(mesh, points, report.seen_distance);
  if (report.seen_fraction < o.invented_warning) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "only %.0f%% of the reconstructed surface lies within %.1f mm of a scan point: the rest is invented; "
                  "scan more sides",
                  100 * report.seen_fraction, 1e3 * report.seen_distance);
    report.warnings.push_back(b);
  }
  return mesh;
}

}  // namespace dmgplace::tools
