#include <iostream>

#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"

namespace dmgplace::cli {

int run_bake_object(const BakeObjectArgs& a) {
  tools::MeshReadOptions opts;
  opts.scale = a.scale;
  tools::MeshReport report;
  formats::ObjectArtifact obj;
  obj.mesh = tools::read_mesh(a.mesh, opts, &report);
  for (const auto& w : report.warnings) std::cerr << "warning: " << a.mesh << ": " << w << "\n";
  obj.mass = tools::compute_mass_properties(obj.mesh, a.mass, a.mesh);
  if (a.com) {
    obj.mass.com = Eigen::Vector3d((*a.com)[0], (*a.com)[1], (*a.com)[2]);
    obj.mass.com_overridden = true;
  }
  nlohmann::json params = {{"mesh", a.mesh}, {"scale", a.scale}, {"mass", a.mass}};
  if (a.com) params["com"] = *a.com;
  obj.header = make_header(params, {a.mesh});
  formats::save_object(std::move(obj), a.out);
  report_written(a.out);
  return 0;
}

}  // namespace dmgplace::cli
