#pragma once
// The geometric path a timed trajectory follows (Kunz & Stilman 2012): straight joint-space
// lines between waypoints, each corner replaced by a circular arc tangent to both of its lines
// that stays within `max_deviation` of the corner and uses at most half of either line.
// Parameterised by arc length s, so the tangent f'(s) is a unit vector; f'' is zero on lines and
// points to the center on arcs. Private to the runtime.
#include <Eigen/Core>
#include <vector>

#include "dmgplace/runtime/types.hpp"

namespace dmgplace::runtime::detail {

// A line or an arc, covering [start, end()] of the path's arc length.
struct PathPiece {
  double start = 0, length = 0;
  Eigen::VectorXd origin;   // the piece's first point
  Eigen::VectorXd tangent;  // unit tangent at origin (a line's direction)
  Eigen::VectorXd outward;  // arc: unit vector from the center to origin; empty for a line
  double radius = 0;        // arc: its radius; 0 for a line
  // Arc: offsets from start, ascending, where some joint's velocity along the arc is zero. The
  // acceleration limit curve has its corners there (between them it is concave), so these are
  // where it has its minima and its switching points.
  std::vector<double> joint_turns;

  bool is_arc() const { return radius > 0; }
  double end() const { return start + length; }
};

class BlendedPath {
 public:
  // `waypoints`: >= 2 points, consecutive ones distinct, no corner too tight to blend (see
  // split_at_stops). max_deviation > 0.
  BlendedPath(const std::vector<Eigen::VectorXd>& waypoints, double max_deviation);

  double length() const { return length_; }
  int piece_count() const { return int(pieces_.size()); }
  const PathPiece& piece(int i) const { return pieces_[std::size_t(i)]; }
  // The piece holding s: [start, end) for piece_after (the last piece at the path's end),
  // (start, end] for piece_before (the first piece at 0). They differ only at a piece boundary.
  int piece_after(double s) const;
  int piece_before(double s) const;

  // f(s), and f'(s), f''(s) into dq, ddq (sized by the caller's first call), on piece `i` with s
  // clamped into it: at a boundary, the piece chosen decides which side's curvature is used.
  Eigen::VectorXd position(int i, double s) const;
  void position(int i, double s, double* q) const;  // into an array of the path's dimension
  void derivatives(int i, double s, Eigen::VectorXd& dq, Eigen::VectorXd& ddq) const;
  // The same into caller-owned arrays of the path's dimension (no allocation: the phase plane
  // evaluates them tens of thousands of times per profile).
  void derivatives(int i, double s, double* dq, double* ddq) const;
  Eigen::Index dimension() const { return pieces_.front().tangent.size(); }

 private:
  void add_arc(const Eigen::VectorXd& corner, const Eigen::VectorXd& in, const Eigen::VectorXd& out, double angle,
               double blend);

  std::vector<PathPiece> pieces_;
  std::vector<double> starts_;
  double length_ = 0;
};

// `path` with each waypoint closer than `tolerance` to the previous kept one dropped; the last
// waypoint is always kept (it replaces a near-duplicate before it) unless all points coincide.
std::vector<Eigen::VectorXd> distinct_waypoints(const JointPath& path, double tolerance);

// Cuts `waypoints` at each corner whose arc would have a radius under 1e-6 (a corner turning
// straight back has none): the arm stops there instead. Each part (>= 2 waypoints) is timed on
// its own, rest to rest.
std::vector<std::vector<Eigen::VectorXd>> split_at_stops(const std::vector<Eigen::VectorXd>& waypoints,
                                                         double max_deviation);

}  // namespace dmgplace::runtime::detail
