#include "dmgplace/tools/object/mass_properties.hpp"

#include <cmath>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

formats::MassProperties compute_mass_properties(const TriMesh& mesh, double mass, const std::string& file) {
  // Second moments of the canonical tetrahedron (0, e1, e2, e3), used for each signed tetrahedron
  // (origin, a, b, c) via C = det(A) A C0 A^T.
  Eigen::Matrix3d c0;
  c0 << 2, 1, 1, 1, 2, 1, 1, 1, 2;
  c0 /= 120.0;
  // Work relative to a point near the mesh so large offsets do not cost precision.
  const Eigen::Vector3d ref = mesh.vertices.colwise().mean().transpose();
  double volume = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    Eigen::Matrix3d a;
    for (int k = 0; k < 3; ++k) a.col(k) = mesh.vertices.row(mesh.triangles(t, k)).transpose() - ref;
    const double det = a.determinant();
    volume += det / 6.0;
    first += det / 24.0 * (a.col(0) + a.col(1) + a.col(2));
    second += det * a * c0 * a.transpose();
  }
  if (!(volume > 0) || !std::isfinite(volume))
    throw Error(file, "mesh", "encloses no positive volume (open or inside-out mesh)");
  formats::MassProperties mp;
  mp.volume = volume;
  mp.mass = mass > 0 ? mass : 1000.0 * volume;
  const double density = mp.mass / volume;
  const Eigen::Vector3d c = first / volume;
  mp.com = c + ref;
  const Eigen::Matrix3d cov = second - volume * c * c.transpose();  // about the COM
  mp.inertia = density * (cov.trace() * Eigen::Matrix3d::Identity() - cov);
  return mp;
}

}  // namespace dmgplace::tools
