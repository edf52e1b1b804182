// time_parameterize against what the trajectory must be, computed here independently: every
// sample within the joint limits, on the path (within max_deviation of the waypoint polyline),
// and as fast as a textbook trapezoid (one segment) or a brute-force phase-plane sweep on a fine
// grid over the blended corner's own geometry (two segments).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "dmgplace/runtime/motion/trajectory.hpp"

using namespace dmgplace::runtime;

namespace {

// The tolerance every limit check allows: relative 1e-6 plus absolute 1e-9 (rounding only; the
// parameterisation keeps its own margin inside the limits).
constexpr double kRel = 1e-6, kAbs = 1e-9;

Eigen::VectorXd vec(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

double distance_to_segment(const Eigen::VectorXd& q, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::VectorXd ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - q).norm();
}

double distance_to_polyline(const std::vector<double>& q, const JointPath& path) {
  double best = (vec(q) - vec(path.front())).norm();
  for (std::size_t i = 1; i < path.size(); ++i)
    best = std::min(best, distance_to_segment(vec(q), vec(path[i - 1]), vec(path[i])));
  return best;
}

// Every sample within the limits; velocities the derivative of positions and accelerations the
// derivative of velocities, as far as the samples show; the ends the waypoints, at rest.
void expect_valid(const Trajectory& tr, const JointPath& path, const JointLimits& lim, const TimingOptions& o) {
  ASSERT_FALSE(tr.empty());
  const std::size_t n = path.front().size();
  ASSERT_EQ(tr.positions.size(), tr.time.size());
  ASSERT_EQ(tr.velocities.size(), tr.time.size());
  ASSERT_EQ(tr.accelerations.size(), tr.time.size());
  EXPECT_EQ(tr.time.front(), 0.0);
  EXPECT_EQ(tr.positions.front(), path.front());
  EXPECT_EQ(tr.positions.back(), path.back());
  for (std::size_t j = 0; j < n; ++j) {
    EXPECT_EQ(tr.velocities.front()[j], 0.0);
    EXPECT_EQ(tr.velocities.back()[j], 0.0);
  }
  for (std::size_t k = 0; k < tr.time.size(); ++k) {
    ASSERT_EQ(tr.positions[k].size(), n);
    for (std::size_t j = 0; j < n; ++j) {
      const double vmax = lim.velocity[j] * o.velocity_scaling, amax = lim.acceleration[j] * o.acceleration_scaling;
      ASSERT_TRUE(std::isfinite(tr.positions[k][j]) && std::isfinite(tr.velocities[k][j]) &&
                  std::isfinite(tr.accelerations[k][j]));
      EXPECT_LE(std::abs(tr.velocities[k][j]), vmax * (1 + kRel) + kAbs) << "sample " << k << " joint " << j;
      EXPECT_LE(std::abs(tr.accelerations[k][j]), amax * (1 + kRel) + kAbs) << "sample " << k << " joint " << j;
      if (k == 0) continue;
      const double dt = tr.time[k] - tr.time[k - 1];
      const double dq = tr.positions[k][j] - tr.positions[k - 1][j];
      const double dv = tr.velocities[k][j] - tr.velocities[k - 1][j];
      EXPECT_LE(std::abs(dq), vmax * dt * (1 + kRel) + kAbs) << "sample " << k << " joint " << j;
      EXPECT_LE(std::abs(dv), amax * dt * (1 + kRel) + kAbs) << "sample " << k << " joint " << j;
      // |v(t) - (v0 + v1) / 2| <= amax dt / 2 inside the step, so the trapezoid rule is off by at
      // most amax dt^2 / 2.
      const double mean_v = 0.5 * (tr.velocities[k][j] + tr.velocities[k - 1][j]);
      EXPECT_LE(std::abs(dq - mean_v * dt), 0.5 * amax * dt * dt * (1 + kRel) + kAbs)
          << "sample " << k << " joint " << j;
    }
    if (k > 0) {
      EXPECT_GT(tr.time[k], tr.time[k - 1]);
    }
    EXPECT_LE(distance_to_polyline(tr.positions[k], path), o.max_deviation * (1 + kRel) + kAbs) << "sample " << k;
  }
}

struct RandomCase {
  JointPath path;
  JointLimits limits;
  TimingOptions options;
};

RandomCase random_case(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1), pos(0, 1);
  const int dof = 1 + int(rng() % 7), points = 2 + int(rng() % 7);
  RandomCase c;
  c.path.assign(std::size_t(points), std::vector<double>(std::size_t(dof)));
  for (auto& q : c.path)
    for (double& x : q) x = 2 * u(rng);
  // Now and then a short hop or a corner turning straight back.
  for (std::size_t i = 1; i + 1 < c.path.size(); ++i) {
    const unsigned kind = rng() % 8;
    if (kind == 0) c.path[i + 1] = c.path[i - 1];
    if (kind == 1)
      for (int j = 0; j < dof; ++j) c.path[i][std::size_t(j)] = c.path[i - 1][std::size_t(j)] + 0.01 * u(rng);
  }
  for (int j = 0; j < dof; ++j) {
    c.limits.velocity.push_back(0.2 + 2.5 * pos(rng));
    c.limits.acceleration.push_back(0.2 + 5 * pos(rng));
  }
  c.options.max_deviation = std::pow(10.0, -3 + 2.5 * pos(rng));
  c.options.velocity_scaling = 0.3 + 0.7 * pos(rng);
  c.options.acceleration_scaling = 0.3 + 0.7 * pos(rng);
  c.options.sample_period = 0.004 + 0.02 * pos(rng);
  return c;
}

// The time-optimal rest-to-rest time along one straight segment of unit direction d and length
// len: the limiting joint fixes the path's speed and acceleration bounds.
double trapezoid_time(const Eigen::VectorXd& d, double len, const Eigen::VectorXd& vmax, const Eigen::VectorXd& amax) {
  double v = std::numeric_limits<double>::infinity(), a = v;
  for (Eigen::Index j = 0; j < d.size(); ++j)
    if (d[j] != 0) v = std::min(v, vmax[j] / std::abs(d[j])), a = std::min(a, amax[j] / std::abs(d[j]));
  return len >= v * v / a ? len / v + v / a : 2 * std::sqrt(len / a);
}

// Two segments q0-q1-q2 with the corner replaced by the arc of Kunz & Stilman (2012): tangent to
// both segments, `blend` from the corner along each, radius blend / tan(angle / 2), centered on
// the corner's bisector. Written from the paper's centered form, not the library's.
struct CornerPath {
  Eigen::VectorXd y1, y2, center, x;
  double line1 = 0, radius = 0, angle = 0, arc = 0, line2 = 0;

  CornerPath(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& c, double max_deviation)
      : y1((b - a).normalized()), y2((c - b).normalized()) {
    angle = std::acos(std::clamp(y1.dot(y2), -1.0, 1.0));
    const double blend = std::min(
        {(b - a).norm() / 2, (c - b).norm() / 2, max_deviation * std::sin(angle / 2) / (1 - std::cos(angle / 2))});
    radius = blend / std::tan(angle / 2);
    center = b + (y2 - y1).normalized() * radius / std::cos(angle / 2);
    x = (b - blend * y1 - center) / radius;
    line1 = (b - a).norm() - blend;
    arc = angle * radius;
    line2 = (c - b).norm() - blend;
  }
  double length() const { return line1 + arc + line2; }
  // f'(s) and f''(s).
  void derivatives(double s, Eigen::VectorXd& d1, Eigen::VectorXd& d2) const {
    if (s < line1) {
      d1 = y1, d2 = Eigen::VectorXd::Zero(y1.size());
    } else if (s < line1 + arc) {
      const double t = (s - line1) / radius;
      d1 = -x * std::sin(t) + y1 * std::cos(t);
      d2 = -(x * std::cos(t) + y1 * std::sin(t)) / radius;
    } else {
      d1 = y2, d2 = Eigen::VectorXd::Zero(y1.size());
    }
  }
};

// Path accelerations the joints allow at speed^2 u: [lo, hi], empty when lo > hi.
std::pair<double, double> path_accel(const Eigen::VectorXd& d1, const Eigen::VectorXd& d2, double u,
                                     const Eigen::VectorXd& amax) {
  double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
  for (Eigen::Index j = 0; j < d1.size(); ++j) {
    if (std::abs(d1[j]) < 1e-12) {
      if (std::abs(d2[j]) * u > amax[j]) return {1, -1};
      continue;
    }
    double a = (-amax[j] - d2[j] * u) / d1[j], b = (amax[j] - d2[j] * u) / d1[j];
    if (a > b) std::swap(a, b);
    lo = std::max(lo, a), hi = std::min(hi, b);
  }
  return {lo, hi};
}

// Brute force: the largest speed^2 at each of n grid points (velocity limits, and by bisection
// the largest u some path acceleration fits), a forward sweep at the largest path acceleration
// and a backward sweep at the smallest, both evaluated at the grid points; the time of the lower
// envelope.
double grid_time(const CornerPath& path, const Eigen::VectorXd& vmax, const Eigen::VectorXd& amax, int n) {
  const double ds = path.length() / n;
  std::vector<Eigen::VectorXd> d1(std::size_t(n) + 1), d2(std::size_t(n) + 1);
  std::vector<double> cap(std::size_t(n) + 1), u(std::size_t(n) + 1);
  for (int i = 0; i <= n; ++i) {
    path.derivatives(i * ds, d1[std::size_t(i)], d2[std::size_t(i)]);
    double top = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < vmax.size(); ++j)
      if (d1[std::size_t(i)][j] != 0) top = std::min(top, std::pow(vmax[j] / d1[std::size_t(i)][j], 2));
    double lo = 0, hi = top;
    const auto fits = [&](double v) {
      const auto r = path_accel(d1[std::size_t(i)], d2[std::size_t(i)], v, amax);
      return r.first <= r.second;
    };
    if (!fits(hi))
      for (int k = 0; k < 100; ++k) (fits(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
    cap[std::size_t(i)] = fits(hi) ? hi : lo;
  }
  u[0] = 0;
  for (int i = 0; i < n; ++i) {
    const auto r = path_accel(d1[std::size_t(i)], d2[std::size_t(i)], u[std::size_t(i)], amax);
    u[std::size_t(i) + 1] = std::clamp(u[std::size_t(i)] + 2 * ds * r.second, 0.0, cap[std::size_t(i) + 1]);
  }
  u[std::size_t(n)] = 0;
  for (int i = n - 1; i >= 0; --i) {
    const auto r = path_accel(d1[std::size_t(i) + 1], d2[std::size_t(i) + 1], u[std::size_t(i) + 1], amax);
    u[std::size_t(i)] = std::min(u[std::size_t(i)], std::max(0.0, u[std::size_t(i) + 1] - 2 * ds * r.first));
  }
  double t = 0;
  for (int i = 0; i < n; ++i) t += 2 * ds / (std::sqrt(u[std::size_t(i)]) + std::sqrt(u[std::size_t(i) + 1]));
  return t;
}

}  // namespace

TEST(TimeParameterization, RandomPathsStayWithinTheLimitsAndTheDeviation) {
  std::mt19937 rng(20240611);
  for (int trial = 0; trial < 200; ++trial) {
    const RandomCase c = random_case(rng);
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_valid(time_parameterize(c.path, c.limits, c.options), c.path, c.limits, c.options);
    if (HasFailure()) break;
  }
}

TEST(TimeParameterization, SamplesEveryPeriodFromZeroAndTheEndExactly) {
  const JointPath path{{0, 0}, {1, 0.5}, {1.5, -0.5}};
  TimingOptions o;
  o.sample_period = 0.03;
  const Trajectory tr = time_parameterize(path, {{1, 1}, {2, 2}}, o);
  ASSERT_GE(tr.time.size(), 3u);
  for (std::size_t k = 0; k + 1 < tr.time.size(); ++k) EXPECT_DOUBLE_EQ(tr.time[k], double(k) * o.sample_period);
  EXPECT_GT(tr.time.back(), tr.time[tr.time.size() - 2]);
  EXPECT_LE(tr.time.back() - tr.time[tr.time.size() - 2], o.sample_period * (1 + 1e-9));
}

TEST(TimeParameterization, SingleSegmentTakesTheAnalyticTrapezoidTime) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1), pos(0, 1);
  for (int trial = 0; trial < 40; ++trial) {
    const int dof = 1 + trial % 7;
    Eigen::VectorXd a(dof), b(dof), vmax(dof), amax(dof);
    for (int j = 0; j < dof; ++j)
      a[j] = u(rng), b[j] = a[j] + (trial % 2 ? 0.05 : 2.0) * u(rng);  // triangles, trapezoids
    for (int j = 0; j < dof; ++j) vmax[j] = 0.2 + 2 * pos(rng), amax[j] = 0.2 + 4 * pos(rng);
    const JointPath path{{a.data(), a.data() + dof}, {b.data(), b.data() + dof}};
    const JointLimits lim{{vmax.data(), vmax.data() + dof}, {amax.data(), amax.data() + dof}};
    const double expected = trapezoid_time((b - a).normalized(), (b - a).norm(), vmax, amax);
    EXPECT_NEAR(time_parameterize(path, lim).duration(), expected, 0.01 * expected) << "trial " << trial;
  }
}

TEST(TimeParameterization, CornerTakesTheBruteForceGridTime) {
  struct Corner {
    JointPath path;
    JointLimits limits;
    double deviation;
  };
  const std::vector<Corner> corners{
      {{{0, 0}, {1, 0}, {1, 1}}, {{1, 1}, {1, 1}}, 0.1},                                 // right angle, arc-limited
      {{{0, 0, 0}, {0.8, 0.3, -0.2}, {0.2, 1.0, 0.4}}, {{2, 0.5, 1}, {3, 1, 2}}, 0.05},  // sharp, unequal limits
      {{{0, 0}, {2, 0.3}, {4, 0}}, {{0.5, 0.5}, {3, 3}}, 0.2},                           // shallow, velocity-limited
      {{{0.1, -0.3, 0.2, 0.0}, {0.9, 0.4, -0.5, 0.3}, {1.2, 1.3, 0.1, -0.4}},
       {{1, 1.5, 0.8, 2}, {1, 2, 1.5, 0.7}},
       0.02},
  };
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Corner& c = corners[i];
    TimingOptions o;
    o.max_deviation = c.deviation;
    const CornerPath geometry(vec(c.path[0]), vec(c.path[1]), vec(c.path[2]), c.deviation);
    const double reference = grid_time(geometry, vec(c.limits.velocity), vec(c.limits.acceleration), 40000);
    const double duration = time_parameterize(c.path, c.limits, o).duration();
    EXPECT_NEAR(duration / reference, 1.0, 0.01)
        << "corner " << i << ": " << duration << " s, grid " << reference << " s";
  }
}

TEST(TimeParameterization, HalfTheVelocityDoublesAVelocityLimitedDuration) {
  // Long segments, fast acceleration: cruising dominates.
  const JointPath path{{0, 0, 0}, {3, 1, -2}, {6, -1, -1}, {8, 2, 1}};
  const JointLimits lim{{0.5, 0.6, 0.4}, {20, 20, 20}};
  TimingOptions full, half;
  half.velocity_scaling = 0.5;
  const double ratio = time_parameterize(path, lim, half).duration() / time_parameterize(path, lim, full).duration();
  EXPECT_NEAR(ratio, 2.0, 0.04);
}

TEST(TimeParameterization, AccelerationScalingStretchesAnAccelerationLimitedDurationByItsInverseRoot) {
  // Short segments, no velocity limit reached: time scales exactly as 1 / sqrt(scaling).
  const JointPath path{{0, 0}, {0.1, 0.05}, {0.15, -0.05}, {0.3, 0}};
  const JointLimits lim{{50, 50}, {1, 2}};
  TimingOptions full, quarter;
  quarter.acceleration_scaling = 0.25;
  const double ratio = time_parameterize(path, lim, quarter).duration() / time_parameterize(path, lim, full).duration();
  EXPECT_NEAR(ratio, 2.0, 0.02);
}

TEST(TimeParameterization, OneWaypointIsOnePointAtRest) {
  const JointLimits lim{{1, 1}, {1, 1}};
  for (const JointPath& path : {JointPath{{0.3, -0.2}}, JointPath{{0.3, -0.2}, {0.3, -0.2}, {0.3, -0.2}}}) {
    const Trajectory tr = time_parameterize(path, lim);
    ASSERT_EQ(tr.time.size(), 1u);
    EXPECT_EQ(tr.time[0], 0.0);
    EXPECT_EQ(tr.positions[0], path[0]);
    EXPECT_EQ(tr.velocities[0], std::vector<double>(2, 0.0));
    EXPECT_EQ(tr.duration(), 0.0);
  }
}

TEST(TimeParameterization, DuplicateWaypointsAreSkipped) {
  const JointLimits lim{{1, 2}, {1.5, 1}};
  const JointPath plain{{0, 0}, {1, 0.5}, {0.5, 1.5}};
  const JointPath doubled{{0, 0}, {0, 0}, {1, 0.5}, {1, 0.5}, {1, 0.5}, {0.5, 1.5}, {0.5, 1.5}};
  const Trajectory tr = time_parameterize(doubled, lim);
  expect_valid(tr, doubled, lim, {});
  EXPECT_NEAR(tr.duration(), time_parameterize(plain, lim).duration(), 1e-9);
}

TEST(TimeParameterization, CollinearWaypointsTakeTheSingleSegmentTime) {
  const JointLimits lim{{1, 0.7, 1.2}, {2, 1, 3}};
  const Eigen::VectorXd a = Eigen::Vector3d(0.1, -0.4, 0.3), b = Eigen::Vector3d(1.3, 0.8, -0.6);
  JointPath path{{a[0], a[1], a[2]}};
  for (double t : {0.2, 0.5, 0.55, 0.9}) {
    const Eigen::VectorXd q = a + t * (b - a);
    path.push_back({q[0], q[1], q[2]});
  }
  path.push_back({b[0], b[1], b[2]});
  const Trajectory tr = time_parameterize(path, lim);
  expect_valid(tr, path, lim, {});
  const double single = time_parameterize(JointPath{path.front(), path.back()}, lim).duration();
  EXPECT_NEAR(tr.duration(), single, 1e-6 * single);
  EXPECT_NEAR(single, trapezoid_time((b - a).normalized(), (b - a).norm(), vec(lim.velocity), vec(lim.acceleration)),
              0.01 * single);
}

TEST(TimeParameterization, ExactReversalStopsAndComesBack) {
  const JointLimits lim{{1, 1}, {1, 1}};
  const JointPath there{{0, 0}, {0.6, 0.3}};
  const JointPath back{{0, 0}, {0.6, 0.3}, {0, 0}};
  const Trajectory tr = time_parameterize(back, lim);
  expect_valid(tr, back, lim, {});
  const double one_way = time_parameterize(there, lim).duration();
  EXPECT_NEAR(tr.duration(), 2 * one_way, 1e-6 * one_way);
  // It reaches the turning point: the farthest sample is there, within a sample's travel.
  double farthest = 0;
  for (const auto& q : tr.positions) farthest = std::max(farthest, vec(q).norm());
  EXPECT_NEAR(farthest, vec(there[1]).norm(), 0.01);
}

TEST(TimeParameterization, RejectsInvalidInput) {
  const JointPath path{{0, 0}, {1, 1}};
  const JointLimits lim{{1, 1}, {1, 1}};
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const auto options = [](double vs, double as, double dev, double period) {
    TimingOptions o;
    o.velocity_scaling = vs, o.acceleration_scaling = as, o.max_deviation = dev, o.sample_period = period;
    return o;
  };
  EXPECT_THROW(time_parameterize({}, lim), std::invalid_argument);
  EXPECT_THROW(time_parameterize({{0, 0}, {1, 1, 1}}, lim), std::invalid_argument);
  EXPECT_THROW(time_parameterize({{0, 0, 0}, {1, 1, 1}}, lim), std::invalid_argument);
  EXPECT_THROW(time_parameterize(path, {{1, 1}, {1}}), std::invalid_argument);
  EXPECT_THROW(time_parameterize({{}, {}}, {{}, {}}), std::invalid_argument);
  EXPECT_THROW(time_parameterize({{0, nan}, {1, 1}}, lim), std::invalid_argument);
  EXPECT_THROW(time_parameterize({{0, 0}, {inf, 1}}, lim), std::invalid_argument);
  for (double bad : {0.0, -1.0, nan, inf}) {
    EXPECT_THROW(time_parameterize(path, {{1, bad}, {1, 1}}), std::invalid_argument) << bad;
    EXPECT_THROW(time_parameterize(path, {{1, 1}, {bad, 1}}), std::invalid_argument) << bad;
  }
  for (double bad : {0.0, -0.5, 1.5, nan}) {
    EXPECT_THROW(time_parameterize(path, lim, options(bad, 1, 0.01, 0.01)), std::invalid_argument) << bad;
    EXPECT_THROW(time_parameterize(path, lim, options(1, bad, 0.01, 0.01)), std::invalid_argument) << bad;
  }
  for (double bad : {0.0, -0.01, nan, inf}) {
    EXPECT_THROW(time_parameterize(path, lim, options(1, 1, bad, 0.01)), std::invalid_argument) << bad;
    EXPECT_THROW(time_parameterize(path, lim, options(1, 1, 0.01, bad)), std::invalid_argument) << bad;
  }
  EXPECT_NO_THROW(time_parameterize(path, lim, options(1, 1, 0.01, 0.01)));
}
