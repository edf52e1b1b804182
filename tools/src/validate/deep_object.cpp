// validate --deep for OBJECT.h5: the mass properties re-derived from the stored mesh. A wrong
// center of mass makes an unstable face look stable; the faces and DMG contacts are already held
// against the mesh by the ordinary validation.
#include <cmath>

#include "dmgplace/tools/object/mass_properties.hpp"
#include "dmgplace/tools/validate/deep_checks.hpp"

namespace dmgplace::tools::detail {
namespace {

// The same integrals over the same mesh agree to rounding; relative to the object's size.
constexpr double kRelativeTolerance = 1e-9;

}  // namespace

void deep_object(const formats::ObjectArtifact& a, const DeepOptions&, DeepReport& report) {
  const formats::MassProperties m = compute_mass_properties(a.mesh, a.mass.mass, report.file);
  const double size = std::cbrt(m.volume);
  DeepCheck volume{"volume from the mesh",
                   "mass/volume_mass",
                   1,
                   std::abs(a.mass.volume - m.volume) / m.volume,
                   kRelativeTolerance,
                   "relative",
                   "stored " + fmt(a.mass.volume) + " m^3, from the mesh " + fmt(m.volume) + " m^3"};
  report.checks.push_back(volume);
  if (a.mass.com_overridden) {
    report.notes.push_back("center of mass given at the bake (--com): not re-derived");
  } else {
    report.checks.push_back({"center of mass from the mesh", "mass/com", 1, (a.mass.com - m.com).norm() / size,
                             kRelativeTolerance, "of the object's size",
                             "stored " + fmt(a.mass.com) + ", from the mesh " + fmt(m.com)});
  }
  const double scale = m.inertia.norm();
  report.checks.push_back({"inertia from the mesh", "mass/inertia", 1, (a.mass.inertia - m.inertia).norm() / scale,
                           kRelativeTolerance, "relative",
                           "stored diagonal " + fmt(Eigen::Vector3d(a.mass.inertia.diagonal())) + ", from the mesh " +
                               fmt(Eigen::Vector3d(m.inertia.diagonal()))});
}

}  // namespace dmgplace::tools::detail
