#include "blended_path.hpp"

#include <algorithm>
#include <cmath>

namespace dmgplace::runtime::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Corners turning less than this are left sharp: the arc would be nearly flat and the tangent's
// jump is below anything a controller sees.
constexpr double kCollinear = 1e-9;
// Corners whose arc would be tighter than this (a corner turning straight back has radius 0) are
// stops instead: the speed on such an arc would be ~sqrt(a r), next to nothing, and the arc's
// angle would drown in the rounding of the path's arc length.
constexpr double kMinRadius = 1e-6;

// Angle between unit directions, accurate near 0 and near pi (where acos is not).
double turn_angle(const Eigen::VectorXd& in, const Eigen::VectorXd& out) {
  return 2 * std::atan2((out - in).norm(), (out + in).norm());
}

// The arc at a corner between segments of lengths len_in and len_out turning by `angle`: it
// starts and ends `blend` from the corner (at most half of either segment) and stays within
// max_deviation of it, blend (1 - cos(angle/2)) / sin(angle/2) from the corner at its middle.
struct CornerArc {
  double blend = 0, radius = 0;  // blend 0: no arc (a straight-through corner)
};

CornerArc corner_arc(double len_in, double len_out, double angle, double max_deviation) {
  if (angle < kCollinear) return {};
  const double quarter_sin = std::sin(angle / 4);
  const double by_deviation = max_deviation * std::sin(angle / 2) / (2 * quarter_sin * quarter_sin);
  const double blend = std::min({len_in / 2, len_out / 2, by_deviation});
  return {blend, blend / std::tan(angle / 2)};
}

Eigen::VectorXd waypoint(const std::vector<double>& q) {
  return Eigen::Map<const Eigen::VectorXd>(q.data(), Eigen::Index(q.size()));
}

}  // namespace

BlendedPath::BlendedPath(const std::vector<Eigen::VectorXd>& waypoints, double max_deviation) {
  const std::size_t m = waypoints.size() - 1;  // segments
  std::vector<Eigen::VectorXd> dir(m);
  std::vector<double> len(m), angle(m + 1, 0.0), blend(m + 1, 0.0);
  for (std::size_t k = 0; k < m; ++k) {
    len[k] = (waypoints[k + 1] - waypoints[k]).norm();
    dir[k] = (waypoints[k + 1] - waypoints[k]) / len[k];
  }
  for (std::size_t k = 1; k < m; ++k) {
    angle[k] = turn_angle(dir[k - 1], dir[k]);
    blend[k] = corner_arc(len[k - 1], len[k], angle[k], max_deviation).blend;
  }
  for (std::size_t k = 0; k < m; ++k) {
    const double line = len[k] - blend[k] - blend[k + 1];
    if (line > 1e-12 * len[k]) {
      PathPiece p;
      p.origin = waypoints[k] + blend[k] * dir[k];
      p.tangent = dir[k];
      p.length = line;
      p.start = length_;
      pieces_.push_back(std::move(p));
      length_ += line;
    }
    if (k + 1 < m && blend[k + 1] > 0) add_arc(waypoints[k + 1], dir[k], dir[k + 1], angle[k + 1], blend[k + 1]);
  }
  for (const PathPiece& p : pieces_) starts_.push_back(p.start);
}

void BlendedPath::add_arc(const Eigen::VectorXd& corner, const Eigen::VectorXd& in, const Eigen::VectorXd& out,
                          double angle, double blend) {
  PathPiece p;
  p.radius = blend / std::tan(angle / 2);
  p.origin = corner - blend * in;
  p.tangent = in;
  const Eigen::VectorXd inward = out - in.dot(out) * in;  // towards the center, norm sin(angle)
  p.outward = -inward / inward.norm();
  p.length = angle * p.radius;
  p.start = length_;
  // Joint j's velocity along the arc, -outward_j sin(t) + tangent_j cos(t), is zero where
  // tan(t) = tangent_j / outward_j: once in [0, pi), and the arc turns by less than pi.
  for (Eigen::Index j = 0; j < in.size(); ++j) {
    if (std::abs(p.tangent[j]) + std::abs(p.outward[j]) < 1e-12) continue;  // joint not on the arc's plane
    double t = std::atan2(p.tangent[j], p.outward[j]);
    if (t < 0) t += kPi;
    if (t > 1e-9 && t < angle - 1e-9) p.joint_turns.push_back(t * p.radius);
  }
  std::sort(p.joint_turns.begin(), p.joint_turns.end());
  p.joint_turns.erase(std::unique(p.joint_turns.begin(), p.joint_turns.end(),
                                  [&](double a, double b) { return b - a < 1e-12 * p.radius; }),
                      p.joint_turns.end());
  pieces_.push_back(std::move(p));
  length_ += pieces_.back().length;
}

int BlendedPath::piece_after(double s) const {
  const auto it = std::upper_bound(starts_.begin(), starts_.end(), s);
  return std::clamp(int(it - starts_.begin()) - 1, 0, piece_count() - 1);
}

int BlendedPath::piece_before(double s) const {
  const auto it = std::lower_bound(starts_.begin(), starts_.end(), s);
  return std::clamp(int(it - starts_.begin()) - 1, 0, piece_count() - 1);
}

Eigen::VectorXd BlendedPath::position(int i, double s) const {
  const PathPiece& p = piece(i);
  const double sigma = std::clamp(s - p.start, 0.0, p.length);
  if (!p.is_arc()) return p.origin + sigma * p.tangent;
  // Relative to the arc's start rather than its center: exact for large radii too.
  const double t = sigma / p.radius, half_sin = std::sin(t / 2);
  return p.origin + p.radius * std::sin(t) * p.tangent - 2 * p.radius * half_sin * half_sin * p.outward;
}

void BlendedPath::position(int i, double s, double* q) const {
  const PathPiece& p = piece(i);
  const double sigma = std::clamp(s - p.start, 0.0, p.length);
  const Eigen::Index n = p.origin.size();
  if (!p.is_arc()) {
    for (Eigen::Index j = 0; j < n; ++j) q[j] = p.origin[j] + sigma * p.tangent[j];
    return;
  }
  const double t = sigma / p.radius, half_sin = std::sin(t / 2);
  const double along = p.radius * std::sin(t), inward = 2 * p.radius * half_sin * half_sin;
  for (Eigen::Index j = 0; j < n; ++j) q[j] = p.origin[j] + along * p.tangent[j] - inward * p.outward[j];
}

void BlendedPath::derivatives(int i, double s, Eigen::VectorXd& dq, Eigen::VectorXd& ddq) const {
  dq.resize(dimension()), ddq.resize(dimension());
  derivatives(i, s, dq.data(), ddq.data());
}

void BlendedPath::derivatives(int i, double s, double* dq, double* ddq) const {
  const PathPiece& p = piece(i);
  const Eigen::Index n = p.tangent.size();
  const double* tangent = p.tangent.data();
  if (!p.is_arc()) {
    for (Eigen::Index j = 0; j < n; ++j) dq[j] = tangent[j], ddq[j] = 0.0;
    return;
  }
  const double* outward = p.outward.data();
  const double t = std::clamp(s - p.start, 0.0, p.length) / p.radius, c = std::cos(t), sn = std::sin(t);
  for (Eigen::Index j = 0; j < n; ++j) {
    dq[j] = c * tangent[j] - sn * outward[j];
    ddq[j] = -(c * outward[j] + sn * tangent[j]) / p.radius;
  }
}

std::vector<Eigen::VectorXd> distinct_waypoints(const JointPath& path, double tolerance) {
  std::vector<Eigen::VectorXd> kept{waypoint(path.front())};
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::VectorXd q = waypoint(path[i]);
    if ((q - kept.back()).norm() > tolerance) {
      kept.push_back(q);
    } else if (i + 1 == path.size() && kept.size() > 1) {
      kept.back() = q;  // the path ends exactly at its last waypoint
      while (kept.size() > 1 && (kept[kept.size() - 2] - q).norm() <= tolerance) kept.erase(kept.end() - 2);
    }
  }
  return kept;
}

std::vector<std::vector<Eigen::VectorXd>> split_at_stops(const std::vector<Eigen::VectorXd>& waypoints,
                                                         double max_deviation) {
  std::vector<std::vector<Eigen::VectorXd>> parts;
  std::vector<Eigen::VectorXd> part{waypoints.front()};
  for (std::size_t k = 1; k < waypoints.size(); ++k) {
    part.push_back(waypoints[k]);
    if (k + 1 == waypoints.size()) break;
    const Eigen::VectorXd in = waypoints[k] - waypoints[k - 1], out = waypoints[k + 1] - waypoints[k];
    const CornerArc arc =
        corner_arc(in.norm(), out.norm(), turn_angle(in.normalized(), out.normalized()), max_deviation);
    if (arc.blend > 0 && !(arc.radius >= kMinRadius)) {
      parts.push_back(std::move(part));
      part = {waypoints[k]};
    }
  }
  parts.push_back(std::move(part));
  return parts;
}

}  // namespace dmgplace::runtime::detail
