#pragma once
// Volume, center of mass and inertia of a closed triangle mesh by exact volume integrals
// (divergence theorem over signed tetrahedra), never the tessellation-biased vertex mean.
#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/object_artifact.hpp"

namespace dmgplace::tools {

// Uniform density; `mass` <= 0 means density 1000 kg/m^3 (water-like). Throws dmgplace::Error
// (naming `file`) when the enclosed volume is not positive.
formats::MassProperties compute_mass_properties(const TriMesh& mesh, double mass, const std::string& file);

}  // namespace dmgplace::tools
