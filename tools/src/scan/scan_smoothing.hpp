#pragma once
// Neighbourhood work on scan points (private to dmgplace_tools). Moving-least-squares smoothing:
// each point projected onto a quadric height field fitted to its neighbours (Gaussian weights),
// its normal the fitted surface's. Written here rather than taken from pcl::MovingLeastSquares, whose Eigen template
// instances collide with OMPL's in one process (a crash in the fit).
#include <Eigen/Core>
#include <vector>

namespace dmgplace::tools::detail {

// Points with fewer than 6 neighbours within `radius` keep their position and get the plane
// normal of what neighbours they have (zero when under 3). Normals are unoriented.
void smooth_points(const std::vector<Eigen::Vector3d>& points, double radius, std::vector<Eigen::Vector3d>& smoothed,
                   std::vector<Eigen::Vector3d>& normals);

// Median distance from a point to its nearest neighbour (over a sample of up to 2000 points);
// 0 for fewer than 2 points.
double median_point_spacing(const std::vector<Eigen::Vector3d>& points);

// Flips each normal that disagrees with the weighted majority of its neighbours' within `radius`
// (two sweeps): a point seen at a grazing angle beside an edge can be turned the wrong way by the
// viewpoint test alone.
void agree_with_neighbours(const std::vector<Eigen::Vector3d>& points, std::vector<Eigen::Vector3d>& normals,
                           double radius);

}  // namespace dmgplace::tools::detail
