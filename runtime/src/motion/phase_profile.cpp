#include "phase_profile.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "switching_points.hpp"

namespace dmgplace::runtime::detail {
namespace {

// Radians of arc per integration step at most. Lines need no cap: their limits are constant.
constexpr double kArcStep = 2.5e-3;
constexpr int kMaxHalvings = 48;
constexpr long kMaxSteps = 20'000'000;
constexpr int kMaxSwitches = 1'000'000;
// Relative: a state this close under the limit curve is on it (within_limits allows 1e-9 over).
constexpr double kOnCurve = 1e-9;

// The far end of a step: reached at (s, u) with s_ddot `a` held over the whole step.
struct Step {
  double s, u, a;
};

enum class Check { ok, ends, interior };
enum class Follow { advanced, leave, blocked };

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error("time_parameterize: " + what); }

// Builds one profile in place: knots_ holds the profile so far, its last knot where forward
// integration stands; backward curves are spliced into it.
class ProfileBuilder {
 public:
  explicit ProfileBuilder(const PhaseLimits& limits)
      : lim_(limits), path_(limits.path()), tiny_(1e-14 * (1 + path_.length())) {}

  std::vector<ProfileKnot> build() {
    knots_ = {{0, 0, 0}};
    double last_switch = -1;
    for (int round = 0;; ++round) {
      if (round > kMaxSwitches) fail("too many switching points");
      double hit = 0;
      if (!forward(hit)) break;
      const std::optional<SwitchingPoint> sp = next_switching_point(lim_, hit, last_switch);
      if (!sp) break;  // nothing to touch before the end: the final braking curve repairs it
      backward(sp->s, settle(sp->s, sp->u));
      last_switch = sp->s;
    }
    backward(path_.length(), 0);
    knots_.front().u = 0;
    return std::move(knots_);
  }

 private:
  // A switching point's u on the limit curve, lowered until the profile can leave it both ways:
  // a braking step back and a step forward of a small length must fit the limits. Near the
  // acceleration limit curve the s_ddot each state allows is a narrow range that moves along
  // the path, and a step of constant s_ddot needs the room below the curve to follow it; at a
  // joint turn, rounding of the turn's position alone takes a little of that room.
  double settle(double s, double u) const {
    const int left = path_.piece_before(s), right = path_.piece_after(s);
    const double back = probe_length(left), ahead = probe_length(right);
    double v = u;
    for (double under = 1e-8; under < 0.3; under *= 4) {
      v = u * (1 - under);
      const Step fwd = accel_step(right, s, v, lim_.accel_max(right, s, v), std::min(s + ahead, path_.length()));
      const Step bwd = brake_step(left, s, v, lim_.accel_min(left, s, v), std::max(s - back, 0.0));
      if (check(right, s, v, fwd.s, fwd.u, fwd.a) == Check::ok &&
          check(left, bwd.s, bwd.u, s, v, bwd.a, true) == Check::ok)
        break;
    }
    return v;
  }

  // A step a thousandth of the longest integration step on the piece.
  double probe_length(int p) const {
    const PathPiece& pc = path_.piece(p);
    return 1e-3 * (pc.is_arc() ? std::min(kArcStep * pc.radius, pc.length) : pc.length);
  }

  // Extends the profile from its last knot: false once at the path's end, true where the limit
  // curve stops it (at `hit`).
  bool forward(double& hit) {
    for (;;) {
      count_step();
      const double s0 = knots_.back().s, u0 = knots_.back().u;
      if (s0 >= path_.length()) return false;
      hit = s0;
      const int p = path_.piece_after(s0);
      const double cap = lim_.max_u(p, s0), velocity_cap = lim_.velocity_max_u(p, s0);
      if (u0 > cap * (1 + 10 * kOnCurve)) return true;  // the curve drops at a piece boundary
      const double target = step_target(p, s0, +1);
      // The velocity limit curve may be followed; the acceleration limit curve only touched.
      const bool velocity_binds = velocity_cap <= cap * (1 + kOnCurve);
      const bool on_curve = velocity_binds && u0 >= velocity_cap * (1 - kOnCurve);
      if (on_curve) {
        const Follow f = follow(p, s0, u0, target);
        if (f == Follow::advanced) continue;
        if (f == Follow::blocked) return true;
      }
      if (accelerate(p, s0, u0, target)) continue;
      // No step at all from just under the velocity limit curve (closer than the crossing's
      // resolution): follow it from there.
      if (on_curve || !velocity_binds || u0 < velocity_cap * (1 - 1e-6) ||
          follow(p, s0, u0, target) != Follow::advanced)
        return true;
    }
  }

  // The farthest a step from s on piece p may go in direction dir: the piece's end, the next
  // joint turn (a corner of the limit curve, kept as a knot) and, on arcs, kArcStep radians.
  double step_target(int p, double s, int dir) const {
    const PathPiece& pc = path_.piece(p);
    double t = dir > 0 ? pc.end() : pc.start;
    if (!pc.is_arc()) return t;
    if (dir > 0) {
      for (double j : pc.joint_turns)
        if (pc.start + j > s + tiny_) {
          t = std::min(t, pc.start + j);
          break;
        }
      return std::min(t, s + kArcStep * pc.radius);
    }
    for (auto j = pc.joint_turns.rbegin(); j != pc.joint_turns.rend(); ++j)
      if (pc.start + *j < s - tiny_) {
        t = std::max(t, pc.start + *j);
        break;
      }
    return std::max(t, s - kArcStep * pc.radius);
  }

  // (sa, ua) - (sb, ub), sa < sb, at s_ddot a: `ends` if either end is outside the limits (the
  // shrunk ones unless `ends_true`), `interior` if the step in between breaks the true limits
  // (it is too long for the path's curvature there), else ok.
  Check check(int p, double sa, double ua, double sb, double ub, double a, bool ends_true = false) const {
    if (!lim_.within_limits(p, sa, ua, a, !ends_true) || !lim_.within_limits(p, sb, ub, a, !ends_true))
      return Check::ends;
    if (!lim_.step_within_limits(p, sa, ua, sb, ub, a)) return Check::interior;
    return Check::ok;
  }

  // A step to s1 at the largest s_ddot both of its ends allow.
  Step accel_step(int p, double s0, double u0, double hi0, double s1) const {
    const double h = s1 - s0, a = std::min(hi0, lim_.reach_max(p, s1, u0, h));
    return {s1, std::max(0.0, u0 + 2 * a * h), a};
  }

  // One step at the largest s_ddot, cut short where it would leave the limits. False when no
  // step is possible: the profile is on the limit curve and cannot stay under it.
  bool accelerate(int p, double s0, double u0, double target) {
    const double hi0 = lim_.accel_max(p, s0, u0);
    double s1 = target;
    if (hi0 < 0) s1 = std::min(s1, s0 + 0.25 * u0 / -hi0);  // slowing down: u stays above u0 / 2
    for (int i = 0; i < kMaxHalvings; ++i) {
      const Step st = accel_step(p, s0, u0, hi0, s1);
      const Check c = check(p, s0, u0, st.s, st.u, st.a);
      if (c == Check::ok) return push(st), true;
      if (c == Check::ends) break;
      s1 = s0 + 0.5 * (s1 - s0);
    }
    // The limit curve lies ahead: the longest step that stays under it, by bisection.
    double good = s0, bad = s1;
    std::optional<Step> best;
    for (int i = 0; i < 100 && bad - good > 4e-16 * std::abs(bad); ++i) {
      const double mid = good + 0.5 * (bad - good);
      const Step st = accel_step(p, s0, u0, hi0, mid);
      // Ends exactly under the curve (no rounding allowance), so that following it from there
      // starts from below.
      if (st.u <= lim_.max_u(p, st.s) && check(p, s0, u0, st.s, st.u, st.a) == Check::ok) {
        good = mid, best = st;
      } else {
        bad = mid;
      }
    }
    if (!best || good - s0 <= tiny_) return false;
    push(*best);
    return true;
  }

  // One step along the velocity limit curve from a knot on it. `leave` where the curve rises
  // faster than the path may accelerate (integrate under it instead); `blocked` where it falls
  // faster than the path may brake, or runs above the acceleration limit curve.
  Follow follow(int p, double s0, double u0, double target) {
    if (0.5 * lim_.max_u_slope(p, s0, +1, true) > lim_.accel_max(p, s0, u0)) return Follow::leave;
    Step st{target, u0, 0};  // the last step tried
    double s1 = target;
    for (int i = 0; i < kMaxHalvings && s1 - s0 > tiny_; ++i) {
      const double u1 = lim_.velocity_max_u(p, s1);
      st = {s1, u1, (u1 - u0) / (2 * (s1 - s0))};
      if (check(p, s0, u0, st.s, st.u, st.a) == Check::ok) return push(st), Follow::advanced;
      s1 = s0 + 0.5 * (s1 - s0);
    }
    // Even the shortest step fails: where the path's largest acceleration falls below what the
    // curve needs (a tangency of the two, a point the slope test above just misses) leave it.
    return st.a > lim_.accel_max(p, st.s, st.u) ? Follow::leave : Follow::blocked;
  }

  void push(const Step& st) {
    knots_.back().a = st.a;
    knots_.push_back({st.s, st.u, 0});
  }

  // A step back from (s1, u1) to s0 at the smallest s_ddot both ends allow.
  Step brake_step(int p, double s1, double u1, double lo1, double s0) const {
    const double h = s1 - s0, a = std::max(lo1, lim_.reach_min(p, s0, u1, -h));
    return {s0, std::max(0.0, u1 - 2 * a * h), a};
  }

  // Integrates backward from (s, u) at the smallest s_ddot until the curve meets the profile,
  // and splices it in: the profile then ends at (s, u).
  void backward(double s_end, double u_end) {
    std::vector<ProfileKnot> back{{s_end, u_end, 0}};  // s decreasing; a: s_ddot up to the previous knot
    for (;;) {
      count_step();
      const double s1 = back.back().s, u1 = back.back().u;
      if (s1 <= 0) fail("a braking curve reached the path's start without meeting the profile");
      const int p = path_.piece_before(s1);
      const double lo1 = lim_.accel_min(p, s1, u1);
      double s0 = step_target(p, s1, -1);
      if (lo1 > 0) s0 = std::max(s0, s1 - 0.25 * u1 / lo1);  // u falls going back: stays above u1 / 2
      for (int i = 0;; ++i) {
        if (i == kMaxHalvings || s1 - s0 <= 0) fail("a braking curve left the limits");
        const Step st = brake_step(p, s1, u1, lo1, s0);
        if (const std::optional<double> x = meets(st.s, s1, u1, st.a)) {
          const double ux = u1 - 2 * st.a * (s1 - *x);
          if (check(p, *x, ux, s1, u1, st.a, true) == Check::ok) return splice(back, {*x, ux, st.a});
        } else if (check(p, st.s, st.u, s1, u1, st.a, true) == Check::ok) {
          back.push_back({st.s, st.u, st.a});
          break;
        }
        s0 = s1 - 0.5 * (s1 - s0);
      }
    }
  }

  // Where the braking line u(s) = u1 - 2 a (s1 - s), s in [s0, s1], meets the profile, the
  // rightmost meeting; none if it stays under it.
  std::optional<double> meets(double s0, double s1, double u1, double a) const {
    const double right = std::min(s1, knots_.back().s);
    if (right < s0) return std::nullopt;
    const auto brake = [&](double s) { return u1 - 2 * a * (s1 - s); };
    const auto profile = [&](std::size_t i, double s) { return knots_[i].u + 2 * knots_[i].a * (s - knots_[i].s); };
    const auto after =
        std::upper_bound(knots_.begin(), knots_.end(), right, [](double v, const ProfileKnot& k) { return v < k.s; });
    std::size_t i = std::size_t(after - knots_.begin()) - 1;  // the last knot at or before `right`
    double xr = right, dr = brake(right) - profile(i, right);
    if (dr >= 0) return right;
    for (;;) {
      const double xl = std::max(knots_[i].s, s0), dl = brake(xl) - profile(i, xl);
      if (dl >= 0) return xl + (xr - xl) * dl / (dl - dr);  // both lines between xl and xr
      if (xl <= s0 || i == 0) return std::nullopt;
      xr = xl, dr = brake(xl) - profile(i - 1, xl), --i;
    }
  }

  void splice(const std::vector<ProfileKnot>& back, const ProfileKnot& meeting) {
    while (knots_.size() > 1 && knots_.back().s >= meeting.s - tiny_) knots_.pop_back();
    append(meeting);
    for (auto k = back.rbegin(); k != back.rend(); ++k) append(*k);
  }

  // Adds a knot; one (numerically) at the last knot's s replaces that knot's state instead.
  void append(const ProfileKnot& k) {
    if (k.s <= knots_.back().s + tiny_) {
      knots_.back().u = k.u, knots_.back().a = k.a;
    } else {
      knots_.push_back(k);
    }
  }

  void count_step() {
    if (++steps_ > kMaxSteps) fail("the phase-plane integration took more than 20 million steps");
  }

  const PhaseLimits& lim_;
  const BlendedPath& path_;
  const double tiny_;  // arc lengths closer than this are one
  std::vector<ProfileKnot> knots_;
  long steps_ = 0;
};

}  // namespace

std::vector<ProfileKnot> time_optimal_profile(const PhaseLimits& limits) { return ProfileBuilder(limits).build(); }

}  // namespace dmgplace::runtime::detail
