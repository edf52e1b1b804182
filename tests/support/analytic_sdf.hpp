#pragma once
// Exact signed distance grids of primitive scenes (boxes, spheres, cylinders), for tests that
// need ground truth independent of the Embree field builder.
#include <memory>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/runtime/geometry/grid3.hpp"

namespace dmgplace::test {

double primitive_signed_distance(const Shape& s, const Eigen::Vector3d& p);
double scene_signed_distance(const Scene& scene, const Eigen::Vector3d& p);
// Grid over `box` at `resolution`, values clamped to `band`.
std::shared_ptr<runtime::Grid3> analytic_sdf(const Scene& scene, const Eigen::AlignedBox3d& box, double resolution,
                                             double band);

}  // namespace dmgplace::test
