// time_parameterize: checks the input, builds the blended path (split where a corner is too
// tight to blend), finds each part's time-optimal profile and samples it. The path geometry,
// the phase plane's limits, its switching points and the integration live in the files named
// after them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "blended_path.hpp"
#include "dmgplace/runtime/motion/trajectory.hpp"
#include "phase_limits.hpp"
#include "phase_profile.hpp"

namespace dmgplace::runtime {
namespace {

using detail::BlendedPath;
using detail::ProfileKnot;

// The phase plane works on limits this much (relative) below the true ones: the room a step of
// constant path acceleration may drift into between its ends (see phase_limits.hpp).
constexpr double kMargin = 1e-6;
constexpr double kDuplicate = 1e-10;  // waypoints closer than this (rad or m) are one
constexpr double kMaxSamples = 1e7;

[[noreturn]] void reject(const std::string& what) { throw std::invalid_argument("time_parameterize: " + what); }

std::string num(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

void check_limits(const std::vector<double>& values, const char* kind) {
  for (std::size_t j = 0; j < values.size(); ++j)
    if (!std::isfinite(values[j]) || values[j] <= 0)
      reject(std::string(kind) + " limit of joint " + std::to_string(j) + " is " + num(values[j]) +
             ", not finite and > 0");
}

void validate(const JointPath& path, const JointLimits& limits, const TimingOptions& o) {
  if (path.empty()) reject("the path is empty");
  const std::size_t n = limits.velocity.size();
  if (limits.acceleration.size() != n)
    reject("velocity limits (" + std::to_string(n) + ") and acceleration limits (" +
           std::to_string(limits.acceleration.size()) + ") differ in size");
  if (n == 0) reject("no joint limits");
  check_limits(limits.velocity, "velocity");
  check_limits(limits.acceleration, "acceleration");
  const auto fraction = [](double x) { return x > 0 && x <= 1; };  // false for NaN
  if (!fraction(o.velocity_scaling)) reject("velocity_scaling " + num(o.velocity_scaling) + " is not in (0, 1]");
  if (!fraction(o.acceleration_scaling))
    reject("acceleration_scaling " + num(o.acceleration_scaling) + " is not in (0, 1]");
  if (!std::isfinite(o.max_deviation) || o.max_deviation <= 0)
    reject("max_deviation " + num(o.max_deviation) + " is not finite and > 0");
  if (!std::isfinite(o.sample_period) || o.sample_period <= 0)
    reject("sample_period " + num(o.sample_period) + " is not finite and > 0");
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path[i].size() != n)
      reject("waypoint " + std::to_string(i) + " has " + std::to_string(path[i].size()) + " values, the limits " +
             std::to_string(n));
    for (double x : path[i])
      if (!std::isfinite(x)) reject("waypoint " + std::to_string(i) + " is not finite");
  }
}

// One part of the path between stops (see split_at_stops), with its profile and the time at
// each knot.
struct TimedPart {
  BlendedPath path;
  std::vector<ProfileKnot> knots;
  std::vector<double> time;  // at each knot, from the part's start
  double start = 0;          // the part's start on the trajectory's clock
};

// Knot times: constant s_ddot between knots, so each interval lasts 2 ds / (s_dot0 + s_dot1).
std::vector<double> knot_times(const std::vector<ProfileKnot>& knots) {
  std::vector<double> t{0.0};
  for (std::size_t i = 1; i < knots.size(); ++i) {
    const double speeds = std::sqrt(knots[i - 1].u) + std::sqrt(knots[i].u);
    if (!(speeds > 0)) throw std::runtime_error("time_parameterize: the profile stops inside the path");
    t.push_back(t.back() + 2 * (knots[i].s - knots[i - 1].s) / speeds);
  }
  return t;
}

// Position, velocity and acceleration at time t (from the part's start) into `row` of `out`.
void sample(const TimedPart& part, double t, Trajectory& out, std::size_t row) {
  // The interval holding t: the last knot at or before it, short of the final knot.
  const std::ptrdiff_t at = std::upper_bound(part.time.begin(), part.time.end(), t) - part.time.begin() - 1;
  const std::size_t i = std::min(part.knots.size() - 2, std::size_t(std::max<std::ptrdiff_t>(0, at)));
  const ProfileKnot& k0 = part.knots[i];
  const ProfileKnot& k1 = part.knots[i + 1];
  const double tau = std::clamp(t - part.time[i], 0.0, part.time[i + 1] - part.time[i]);
  const double sd0 = std::sqrt(k0.u), sd = std::max(0.0, sd0 + k0.a * tau);
  const double s = std::clamp(k0.s + sd0 * tau + 0.5 * k0.a * tau * tau, k0.s, k1.s);
  const int piece = part.path.piece_after(0.5 * (k0.s + k1.s));  // an interval lies in one piece
  const std::size_t n = std::size_t(part.path.dimension());
  std::vector<double>&q = out.positions[row], &v = out.velocities[row], &a = out.accelerations[row];
  q.resize(n), v.resize(n), a.resize(n);
  part.path.position(piece, s, q.data());
  part.path.derivatives(piece, s, v.data(), a.data());  // f', f'' first, scaled in place
  for (std::size_t j = 0; j < n; ++j) {
    const double dq = v[j], ddq = a[j];
    v[j] = dq * sd, a[j] = dq * k0.a + ddq * (sd * sd);
  }
}

Trajectory at_rest(const std::vector<double>& q) {
  Trajectory out;
  out.time = {0.0};
  out.positions = {q};
  out.velocities = out.accelerations = {std::vector<double>(q.size(), 0.0)};
  return out;
}

Trajectory sample_parts(const std::vector<TimedPart>& parts, const JointPath& path, double period) {
  const double duration = parts.back().start + parts.back().time.back();
  if (duration / period > kMaxSamples)
    reject("sample_period " + num(period) + " would give more than 10 million points");
  // Every period from 0, and the end; a multiple of the period within a millionth of it of the
  // end is dropped rather than kept as a near-duplicate time.
  const std::size_t regular = std::max<std::size_t>(1, std::size_t(std::ceil(duration / period - 1e-6)));
  Trajectory out;
  out.time.reserve(regular + 1);
  for (std::size_t k = 0; k < regular; ++k) out.time.push_back(double(k) * period);
  out.time.push_back(duration);
  out.positions.resize(out.time.size());
  out.velocities.resize(out.time.size());
  out.accelerations.resize(out.time.size());
  std::size_t part = 0;
  for (std::size_t row = 0; row < out.time.size(); ++row) {
    while (part + 1 < parts.size() && out.time[row] >= parts[part + 1].start) ++part;
    sample(parts[part], out.time[row] - parts[part].start, out, row);
  }
  // The ends exactly: the waypoints themselves, at rest.
  out.positions.front() = path.front();
  out.positions.back() = path.back();
  std::fill(out.velocities.front().begin(), out.velocities.front().end(), 0.0);
  std::fill(out.velocities.back().begin(), out.velocities.back().end(), 0.0);
  return out;
}

}  // namespace

Trajectory time_parameterize(const JointPath& path, const JointLimits& limits, const TimingOptions& options) {
  validate(path, limits, options);
  const std::vector<Eigen::VectorXd> waypoints = detail::distinct_waypoints(path, kDuplicate);
  if (waypoints.size() == 1) return at_rest(path.front());
  const Eigen::Index n = Eigen::Index(limits.velocity.size());
  const Eigen::VectorXd vmax = Eigen::Map<const Eigen::VectorXd>(limits.velocity.data(), n) * options.velocity_scaling;
  const Eigen::VectorXd amax =
      Eigen::Map<const Eigen::VectorXd>(limits.acceleration.data(), n) * options.acceleration_scaling;
  std::vector<TimedPart> parts;
  for (const std::vector<Eigen::VectorXd>& part_points : detail::split_at_stops(waypoints, options.max_deviation)) {
    TimedPart part{BlendedPath(part_points, options.max_deviation), {}, {}, 0.0};
    part.knots = detail::time_optimal_profile(detail::PhaseLimits(part.path, vmax, amax, kMargin));
    part.time = knot_times(part.knots);
    part.start = parts.empty() ? 0.0 : parts.back().start + parts.back().time.back();
    parts.push_back(std::move(part));
  }
  return sample_parts(parts, path, options.sample_period);
}

}  // namespace dmgplace::runtime
