#pragma once
// Gaps between convex solids given by their support functions (boxes, cylinders, spheres, the hull
// of a point set), by GJK. The answer is GJK's dual bound: for the direction v of any iterate,
// every point of A - B lies at least v.w / |v| along v, w being A - B's support point against v.
// That bound is rigorous whatever the simplex arithmetic does (it needs only exact supports), so
// a positive answer proves the solids apart by at least that much.
#include <optional>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::runtime {

class ConvexSolid {
 public:
  static ConvexSolid box(const Eigen::Vector3d& half_extents);
  static ConvexSolid cylinder(double radius, double half_length);  // along local z, centered
  static ConvexSolid sphere(double radius);
  static ConvexSolid hull(const std::vector<Eigen::Vector3d>& points);  // at least one point
  // The hull given as its closed, convex triangulated surface (indices into points, as a stored
  // hull passes formats::hull_problem): supports then climb its edges instead of scanning every
  // vertex.
  static ConvexSolid hull(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3i>& triangles);
  // A shape in its own frame (Shape::origin not applied): a mesh through its hull; nothing for a
  // mesh without a hull.
  static std::optional<ConvexSolid> of(const Shape& shape);

  // The solid's farthest point along d (local frame; d need not be unit).
  Eigen::Vector3d support(const Eigen::Vector3d& d) const {
    int start = -1;
    return support(d, start);
  }
  // The same; `start` is a hull vertex to climb from, updated to the answer's (-1: none yet).
  // Successive directions that change little (GJK's) then cost a step or two each.
  Eigen::Vector3d support(const Eigen::Vector3d& d, int& start) const;
  // A ball around the solid (local frame): the broad phase.
  const Eigen::Vector3d& center() const { return center_; }
  double radius() const { return radius_; }
  // How far a climbed support may fall short of the farthest vertex when the surface is convex
  // only to the stored hull check's tolerance (1e-9 of its extent): ten times that.
  double climb_slack() const { return first_.empty() ? 0.0 : 1e-8 * (center_.norm() + radius_); }

 private:
  enum class Kind { Box, Cylinder, Sphere, Hull } kind_ = Kind::Sphere;
  Eigen::Vector3d size_ = Eigen::Vector3d::Zero();  // box: half extents; cylinder: radius, half length
  std::vector<double> x_, y_, z_;                   // hull vertices
  // Hull surface edges (neighbours of vertex i: adjacent_[first_[i] .. first_[i+1]]); empty: scan.
  std::vector<int> first_, adjacent_;
  std::vector<int> seeds_;  // the vertices farthest along 14 fixed directions: where a climb starts
  Eigen::Vector3d scan(const Eigen::Vector3d& d, int& at) const;
  double along(int i, const Eigen::Vector3d& d) const {
    return x_[std::size_t(i)] * d.x() + y_[std::size_t(i)] * d.y() + z_[std::size_t(i)] * d.z();
  }
  Eigen::Vector3d center_ = Eigen::Vector3d::Zero();
  double radius_ = 0;
};

// Where the last query of the same two solids ended (world frame): GJK's last direction and the
// hull vertices its supports climbed to. Successive queries along a motion move the solids a
// little, so starting there usually proves what the caller needs with the first support. Only a
// start: any direction gives a rigorous bound, so a stale hint costs iterations, never correctness.
struct GapHint {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // zero: no hint (start between the centers)
  int from_a = -1, from_b = -1;
};

// A lower bound on the distance between a (placed by ta) and b (placed by tb): never above the
// true distance; <= 0 when no gap is proven (touching, overlapping, or too close to tell).
// Iterates until the bound is within `tolerance` of GJK's upper estimate, or is above `enough`
// (a caller needing only that much stops there: a sign takes a few iterations where the distance
// takes many). A sign query (enough <= 0) also stops once GJK's upper estimate shows the bound
// cannot get there; with enough > 0 the bound is then refined as without it.
// `hint` (optional): where to start, updated to where this query ended.
// `separation` (optional): the unit direction n the bound was proven along: every point of a lies
// at least the returned bound farther along n than every point of b (a separating plane's normal,
// for bounds on how fast the gap can close: directional certificates). Zero when none was proven.
double convex_gap(const ConvexSolid& a, const Eigen::Isometry3d& ta, const ConvexSolid& b, const Eigen::Isometry3d& tb,
                  double tolerance = 1e-5, double enough = std::numeric_limits<double>::infinity(),
                  GapHint* hint = nullptr, Eigen::Vector3d* separation = nullptr);

}  // namespace dmgplace::runtime
