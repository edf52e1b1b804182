#pragma once
// Covers a rigid body's collision geometry with a few spheres whose union contains it: the fast
// collision layer checks these spheres against the environment's distance field.
#include <vector>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::tools {

struct Sphere {
  Eigen::Vector3d center;
  double radius = 0;
};

struct SphereCoverOptions {
  double sample_spacing = 0.005;  // metres between sample points on and inside the geometry
  double max_radius = 0.08;       // split any sphere larger than this
  double max_excess = 0.015;      // and any whose radius exceeds half its median extent by more
  int max_spheres = 6;
};

// Spheres in the shapes' parent frame. Every sample point (surface and interior, at
// `sample_spacing`) lies inside a sphere, and radii are inflated by the spacing so the continuous
// geometry between samples is covered too.
std::vector<Sphere> cover_with_spheres(const std::vector<Shape>& shapes, const SphereCoverOptions& options = {});

// Points on the surface and inside the shapes, about `spacing` apart (parent frame).
std::vector<Eigen::Vector3d> sample_solid(const std::vector<Shape>& shapes, double spacing);

}  // namespace dmgplace::tools
