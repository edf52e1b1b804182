// Invariants of OBJECT.h5 (`dmgplace validate`): mass, placement faces and the DMG.
#include <cmath>
#include <set>
#include <utility>

#include "dmgplace/formats/object_artifact.hpp"
#include "format_util.hpp"
#include "point_mesh_distance.hpp"

namespace dmgplace::formats {
namespace {

constexpr double kMinAngleStepDeg = 0.1;  // 3600 finger angles: far finer than any gripper needs

bool unit(const Eigen::Vector3d& v) { return v.allFinite() && std::abs(v.norm() - 1) < 1e-6; }

// Smallest signed distance from q to the polygon's edges (positive inside), polygon CCW about n.
double inside_distance(const std::vector<Eigen::Vector3d>& poly, const Eigen::Vector3d& n, const Eigen::Vector3d& q) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector3d& a = poly[i];
    const Eigen::Vector3d e = poly[(i + 1) % poly.size()] - a;
    if (e.norm() == 0) continue;
    d = std::min(d, n.dot(e.cross(q - a)) / e.norm());
  }
  return d;
}

void check_placement(const ObjectArtifact& a, double scale, std::vector<std::string>& p) {
  const auto& pl = a.placement;
  if (!(pl.merge_angle >= 0) || !(pl.required_margin >= 0)) p.push_back("placement/settings: negative or not finite");
  for (std::size_t i = 0; i < pl.faces.size(); ++i) {
    const auto& f = pl.faces[i];
    const std::string w = "placement face " + std::to_string(i) + ": ";
    if (!unit(f.normal)) {
      p.push_back(w + "normal is not unit length");
      continue;
    }
    if (!std::isfinite(f.margin) || !std::isfinite(f.height)) {
      p.push_back(w + "margin or height not finite");
      continue;
    }
    if (f.polygon.size() < 3) {
      p.push_back(w + "polygon has fewer than 3 points");
      continue;
    }
    const double tol = 1e-6 + 1e-6 * scale;
    double support = -std::numeric_limits<double>::infinity();
    for (Eigen::Index v = 0; v < a.mesh.vertices.rows(); ++v)
      support = std::max(support, f.normal.dot(a.mesh.vertices.row(v).transpose()));
    if (std::abs(support - f.height) > tol) p.push_back(w + "height does not match the mesh's extent along the normal");
    for (const auto& q : f.polygon)
      if (!q.allFinite() || std::abs(f.normal.dot(q) - support) > tol) {
        p.push_back(w + "polygon point off the face plane");
        break;
      }
    if (!(std::abs(f.rotation.norm() - 1) <= 1e-6) ||
        !((f.rotation * f.normal - Eigen::Vector3d(0, 0, -1)).norm() <= 1e-6))
      p.push_back(w + "rotation does not turn the normal to -z");
    const double inside = inside_distance(f.polygon, f.normal, a.mass.com);
    if (inside < 0) p.push_back(w + "COM projection outside the polygon");
    else if (inside < pl.required_margin - tol || std::abs(inside - f.margin) > tol)
      p.push_back(w + "stability margin wrong or below the required margin");
  }
}

void check_dmg(const ObjectArtifact& a, double scale, std::vector<std::string>& p) {
  const Dmg& d = a.dmg;
  if (!(d.angle_step_deg >= kMinAngleStepDeg && d.angle_step_deg <= 360)) {
    // Every consumer sizes per-node arrays by 360 / step: refuse before anything divides by it.
    p.push_back("dmg/settings: angle step " + std::to_string(d.angle_step_deg) + " outside [" +
                std::to_string(kMinAngleStepDeg) + ", 360] degrees");
    return;
  }
  const int k = d.angle_count();
  if (std::abs(k * d.angle_step_deg - 360) > 1e-9) p.push_back("dmg/settings: angle step does not divide 360 degrees");
  if (!(d.seed_resolution > 0) || !std::isfinite(d.seed_resolution) || !(d.normal_threshold >= 0) ||
      !std::isfinite(d.normal_threshold))
    p.push_back("dmg/settings: seed resolution must be positive and normal threshold non-negative, both finite");
  if (d.patch_count < 0) p.push_back("dmg/settings: negative patch count");
  const auto& g = d.gripper;
  const bool finite = std::isfinite(g.max_opening) && std::isfinite(g.finger_length) && std::isfinite(g.finger_width) &&
                      std::isfinite(g.finger_thickness) && std::isfinite(g.tip_offset) && g.palm_size.allFinite() &&
                      std::isfinite(g.contact_tolerance);
  if (!(finite && g.max_opening > 0 && g.finger_length > 0 && g.finger_width > 0 && g.finger_thickness > 0 &&
        g.palm_size.minCoeff() > 0 && g.palm_center.allFinite() && g.contact_tolerance >= 0))
    p.push_back("dmg/gripper: sizes must be positive and finite");
  const int facets = int(d.facet_normals.size());
  for (int f = 0; f < facets; ++f)
    if (!unit(d.facet_normals[f]) || !unit(d.facet_zero_axes[f]) ||
        std::abs(d.facet_normals[f].dot(d.facet_zero_axes[f])) > 1e-6)
      p.push_back("dmg facet " + std::to_string(f) + ": normal / zero axis not an orthonormal pair");
  const double tol = 1e-7 + 1e-4 * scale;
  const detail::SurfaceIndex surface(a.mesh, tol);
  for (std::size_t i = 0; i < d.nodes.size(); ++i) {
    const auto& n = d.nodes[i];
    const std::string w = "dmg node " + std::to_string(i) + ": ";
    if (n.patch < 0 || n.patch >= d.patch_count || n.opposite_patch < 0 || n.opposite_patch >= d.patch_count ||
        n.facet < 0 || n.facet >= facets)
      p.push_back(w + "patch or facet index out of range");
    if (n.first_angle < 0 || n.first_angle >= k || n.angle_count < 1 || n.angle_count > k)
      p.push_back(w + "angle interval outside [0, 360)");
    if (!unit(n.normal) || !unit(n.zero_axis) || !unit(n.opposite_normal) ||
        std::abs(n.normal.dot(n.zero_axis)) > 1e-6) {
      p.push_back(w + "normal, zero axis or opposite normal not unit / orthogonal");
      continue;
    }
    if (!surface.near(n.position, tol)) p.push_back(w + "contact point not on the mesh surface");
    if (!surface.near(n.opposite_point, tol)) p.push_back(w + "opposite contact not on the mesh surface");
    if ((n.position - n.opposite_point).norm() > g.max_opening + tol)
      p.push_back(w + "grasp wider than the maximum opening");
  }
  std::set<std::pair<int, int>> edges;
  const int nodes = int(d.nodes.size());
  std::size_t bad = 0;
  for (auto [x, y] : d.edges) {
    if (x < 0 || y < 0 || x >= nodes || y >= nodes || x == y) {
      if (bad++ == 0)
        p.push_back("dmg/edges: index out of range or self loop (" + std::to_string(x) + ", " + std::to_string(y) +
                    ")");
      continue;
    }
    edges.insert({x, y});
  }
  if (bad > 1) p.push_back("dmg/edges: " + std::to_string(bad) + " edges out of range or self loops in all");
  for (auto [x, y] : edges)
    if (!edges.contains({y, x})) {
      p.push_back("dmg/edges: edge " + std::to_string(x) + " -> " + std::to_string(y) + " has no reverse");
      break;
    }
}

}  // namespace

std::vector<std::string> check_object(const ObjectArtifact& a) {
  auto p = detail::check_mesh_indices(a.mesh, "mesh");
  const auto& m = a.mass;
  if (!(m.volume > 0) || !std::isfinite(m.volume)) p.push_back("mass/volume: must be positive and finite");
  if (!(m.mass > 0) || !std::isfinite(m.mass)) p.push_back("mass/mass: must be positive and finite");
  if (!m.com.allFinite()) p.push_back("mass/com: not finite");
  if (!m.inertia.allFinite() || (m.inertia - m.inertia.transpose()).norm() > 1e-9 * (1 + m.inertia.norm()))
    p.push_back("mass/inertia: not a finite symmetric matrix");
  if (!p.empty() || a.mesh.empty()) return p;
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < a.mesh.vertices.rows(); ++i) box.extend(a.mesh.vertices.row(i).transpose());
  if (box.min().cwiseAbs().maxCoeff() > kMaxGeometryExtent || box.max().cwiseAbs().maxCoeff() > kMaxGeometryExtent) {
    p.push_back("mesh: a vertex beyond " + std::to_string(int(kMaxGeometryExtent)) + " m");
    return p;  // the checks below scale their tolerances by the mesh's size
  }
  const double scale = box.diagonal().norm();
  if (box.exteriorDistance(m.com) > 1e-6 + 1e-3 * scale) p.push_back("mass/com: outside the mesh's bounding box");
  check_placement(a, scale, p);
  const std::size_t before = p.size();
  check_dmg(a, scale, p);
  if (p.size() == before)
    detail::append(p, check_grasp_graph_table(a.dmg, a.grasp_graph));  // built on a sound DMG only
  return p;
}

}  // namespace dmgplace::formats
