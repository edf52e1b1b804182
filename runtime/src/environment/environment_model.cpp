#include "dmgplace/runtime/environment/environment_model.hpp"

#include <stdexcept>
#include <utility>

namespace dmgplace::runtime {
namespace {

Grid3 take_grid(formats::FieldGrid&& f) { return Grid3(f.origin, f.resolution, f.dims, std::move(f.values)); }

}  // namespace

Grid3 to_grid(const formats::FieldGrid& field) {
  formats::FieldGrid copy = field;
  return take_grid(std::move(copy));
}

EnvironmentModel make_environment_model(formats::EnvironmentArtifact&& a) {
  EnvironmentModel m;
  m.volume = a.volume;
  m.sdf_signed = a.sdf_signed;
  m.sdf_band = a.sdf.band;
  m.clearance_band = a.clearance.band;
  if (!a.sdf.empty()) m.sdf = std::make_shared<const Grid3>(take_grid(std::move(a.sdf)));
  if (!a.clearance.empty()) m.clearance = std::make_shared<const Grid3>(take_grid(std::move(a.clearance)));
  m.regions = std::move(a.regions);
  return m;
}

}  // namespace dmgplace::runtime
