#include "dmgplace/formats/object_artifact.hpp"

#include <cmath>

#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "format_util.hpp"

namespace dmgplace::formats {

void save_object(ObjectArtifact a, const std::filesystem::path& path) {
  a.header.schema = kObjectSchema;
  a.header.schema_version = kObjectSchemaVersion;
  H5Writer w(path, a.header);
  detail::write_mesh(w, "mesh", a.mesh);
  const auto& m = a.mass;
  double scalars[2] = {m.volume, m.mass};
  w.write("mass/volume_mass", std::span<const double>(scalars), {2});
  w.write("mass/com", std::span<const double>(m.com.data(), 3), {3});
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> inertia = m.inertia;
  w.write("mass/inertia", std::span<const double>(inertia.data(), 9), {3, 3});
  w.attribute("mass", "com_overridden", m.com_overridden ? "true" : "false");
  w.commit();
}

ObjectArtifact load_object(const std::filesystem::path& path) {
  H5Reader r(path);
  r.require_schema(kObjectSchema, kObjectSchemaVersion);
  ObjectArtifact a;
  a.header = r.header();
  a.mesh = detail::read_mesh(r, "mesh");
  auto vm = r.read_f64("mass/volume_mass", {2});
  a.mass.volume = vm.data[0];
  a.mass.mass = vm.data[1];
  auto com = r.read_f64("mass/com", {3});
  a.mass.com = Eigen::Vector3d(com.data[0], com.data[1], com.data[2]);
  auto in = r.read_f64("mass/inertia", {3, 3});
  a.mass.inertia = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(in.data.data());
  a.mass.com_overridden = r.attribute("mass", "com_overridden").value_or("false") == "true";
  return a;
}

std::vector<std::string> check_object(const ObjectArtifact& a) {
  auto p = detail::check_mesh_indices(a.mesh, "mesh");
  const auto& m = a.mass;
  if (!(m.volume > 0) || !std::isfinite(m.volume)) p.push_back("mass/volume: must be positive and finite");
  if (!(m.mass > 0) || !std::isfinite(m.mass)) p.push_back("mass/mass: must be positive and finite");
  if (!m.com.allFinite()) p.push_back("mass/com: not finite");
  if (!m.inertia.allFinite() || (m.inertia - m.inertia.transpose()).norm() > 1e-9 * (1 + m.inertia.norm()))
    p.push_back("mass/inertia: not a finite symmetric matrix");
  if (p.empty() && !a.mesh.empty()) {
    Eigen::AlignedBox3d box;
    for (Eigen::Index i = 0; i < a.mesh.vertices.rows(); ++i) box.extend(a.mesh.vertices.row(i).transpose());
    const double slack = 1e-6 + 1e-3 * box.diagonal().norm();
    if (box.exteriorDistance(m.com) > slack) p.push_back("mass/com: outside the mesh's bounding box");
  }
  return p;
}

Summary summarize_object(const ObjectArtifact& a) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < a.mesh.vertices.rows(); ++i) box.extend(a.mesh.vertices.row(i).transpose());
  Summary s;
  s.emplace_back("vertices", std::to_string(a.mesh.vertices.rows()));
  s.emplace_back("triangles", std::to_string(a.mesh.triangles.rows()));
  s.emplace_back("bounds_min", detail::fmt(Eigen::Vector3d(box.min())));
  s.emplace_back("bounds_max", detail::fmt(Eigen::Vector3d(box.max())));
  s.emplace_back("volume_m3", detail::fmt(a.mass.volume));
  s.emplace_back("mass_kg", detail::fmt(a.mass.mass));
  s.emplace_back("com", detail::fmt(a.mass.com));
  return s;
}

}  // namespace dmgplace::formats
