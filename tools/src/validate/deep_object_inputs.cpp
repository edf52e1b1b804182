// validate --deep --check-inputs for OBJECT.h5 baked from a mesh file: the stored mesh against the
// file read again as the bake read it (its recorded scale), and the stored mass against the
// recorded --mass (or the default density times the volume).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "dmgplace/formats/stale_inputs.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/validate/deep_checks.hpp"

namespace dmgplace::tools::detail {
namespace {

constexpr double kDefaultDensity = 1000;  // kg/m^3: compute_mass_properties' default

bool is_scan(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".pcd";
}

DeepCheck mesh_against(const formats::ObjectArtifact& a, const TriMesh& read, const std::string& input) {
  DeepCheck c{"mesh equal to " + input + " read again", "mesh/vertices", int(read.vertices.rows()), 0, 1e-12, "m", ""};
  if (read.vertices.rows() != a.mesh.vertices.rows() || read.triangles.rows() != a.mesh.triangles.rows() ||
      read.triangles != a.mesh.triangles) {
    c.worst = std::numeric_limits<double>::infinity();
    c.worst_sample = "stored " + std::to_string(a.mesh.vertices.rows()) + " vertices, " +
                     std::to_string(a.mesh.triangles.rows()) + " triangles; the input " +
                     std::to_string(read.vertices.rows()) + ", " + std::to_string(read.triangles.rows()) +
                     " (or other triangles)";
    return c;
  }
  WorstOf w;
  for (Eigen::Index v = 0; v < read.vertices.rows(); ++v) {
    const Eigen::Vector3d s = a.mesh.vertices.row(v).transpose(), r = read.vertices.row(v).transpose();
    w.add((s - r).norm(), [&] { return "vertex " + std::to_string(v) + ": stored " + fmt(s) + ", input " + fmt(r); });
  }
  c.worst = w.worst, c.worst_sample = w.sample;
  return c;
}

}  // namespace

void object_against_inputs(const formats::ObjectArtifact& a, const std::filesystem::path& file, DeepReport& report) {
  const auto params = nlohmann::json::parse(a.header.parameters_json, nullptr, false);
  const auto inputs = formats::check_inputs(file);
  if (params.is_discarded() || inputs.size() != 1 || is_scan(inputs[0].path)) {
    report.notes.push_back("not baked from one mesh file: mesh and mass not compared with inputs");
    return;
  }
  if (inputs[0].at.empty()) {
    report.notes.push_back("input " + inputs[0].path + " not found: mesh and mass not compared");
    return;
  }
  MeshReadOptions o;
  o.scale = params.value("scale", 1.0);
  report.checks.push_back(mesh_against(a, read_mesh(inputs[0].at, o), inputs[0].path));
  const double given = params.value("mass", 0.0);
  const double expected = given > 0 ? given : kDefaultDensity * a.mass.volume;
  report.checks.push_back(
      {"mass as the bake was asked (" + std::string(given > 0 ? "--mass" : "default density x volume") + ")",
       "mass/volume_mass", 1, std::abs(a.mass.mass - expected) / expected, 1e-9, "relative",
       "stored " + fmt(a.mass.mass) + " kg, expected " + fmt(expected) + " kg"});
}

}  // namespace dmgplace::tools::detail
