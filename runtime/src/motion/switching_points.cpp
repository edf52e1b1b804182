#include "switching_points.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace dmgplace::runtime::detail {
namespace {

// Radians of arc between scan points. On lines the limit curve is flat (no switching point
// inside); on arcs it is smooth between joint turns, which are always scanned.
constexpr double kScanStep = 5e-3;

// The limit curve at one side of a point: its value u and g = 2 s_ddot_min(s, u) - slope. With
// g > 0 a profile on the curve rises above it even braking as hard as it may (the curve cannot
// be followed there); with g <= 0 it stays under.
struct Probe {
  double s, u, g;
};

enum class Side { left = -1, both = 0, right = 1 };

class Scanner {
 public:
  Scanner(const PhaseLimits& limits, double from, double after)
      : lim_(limits), path_(limits.path()), from_(from), after_(after), eps_(1e-14 * (1 + path_.length())) {}

  std::optional<SwitchingPoint> run() {
    int p = path_.piece_after(from_);
    if (p > 0 && from_ <= path_.piece(p).start) feed(p - 1, probe(p - 1, from_, Side::left));
    for (; p < path_.piece_count(); ++p)
      for (const auto& [s, side] : scan_points(p))
        if (auto sp = feed(p, probe(p, s, side))) return sp;
    return std::nullopt;
  }

 private:
  Probe probe(int piece, double s, Side side) const {
    const double slope = lim_.max_u_slope(piece, s, int(side));
    return {s, lim_.max_u(piece, s), 2 * lim_.side_accel_range(piece, s, int(side)).lo - slope};
  }

  // The points of `piece` from `from_` on, in order, with the side each is probed from: the
  // start from the right, the end from the left, joint turns (corners of the curve) from both.
  std::vector<std::pair<double, Side>> scan_points(int piece) const {
    const PathPiece& pc = path_.piece(piece);
    const double first = std::max(from_, pc.start);
    std::vector<std::pair<double, Side>> pts;
    if (pc.is_arc()) {
      for (double t : pc.joint_turns) {
        if (pc.start + t < first - eps_) continue;
        const double s = std::max(first, pc.start + t);  // a turn at `first` is probed there
        pts.emplace_back(s, Side::left);
        pts.emplace_back(s, Side::right);
      }
      const double step = kScanStep * pc.radius;
      for (double s = pc.start + step * std::floor((first - pc.start) / step + 1); s < pc.end(); s += step)
        pts.emplace_back(s, Side::both);
      std::stable_sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    }
    if (pts.empty() || pts.front().first > first) pts.insert(pts.begin(), {first, Side::right});
    if (pc.end() > first) pts.emplace_back(pc.end(), Side::left);
    return pts;
  }

  // Takes the next probe; a switching point if the curve between it and the previous probe
  // holds one.
  std::optional<SwitchingPoint> feed(int piece, const Probe& b) {
    const std::optional<Probe> prev = std::exchange(prev_, b);
    if (!prev) return std::nullopt;
    const Probe& a = *prev;
    if (b.s - a.s <= eps_) return at_point(a, b);
    if (a.g > 0 && b.g <= 0) return between(piece, a, b);
    return std::nullopt;
  }

  // a, b: the two sides of one point. Where the curve drops, the lower side need only be
  // followable to the right; where it rises, the profile braking into it from the left must stay
  // under the left side; where it is continuous (a corner), both.
  std::optional<SwitchingPoint> at_point(const Probe& a, const Probe& b) const {
    bool touch;
    double u;
    if (a.u > b.u * (1 + 1e-12)) {
      touch = b.g <= 0, u = b.u;
    } else if (b.u > a.u * (1 + 1e-12)) {
      touch = a.g >= 0, u = a.u;
    } else {
      touch = a.g >= 0 && b.g <= 0, u = std::min(a.u, b.u);
    }
    if (!touch || !eligible(b.s)) return std::nullopt;
    return SwitchingPoint{b.s, u};
  }

  // g changes from > 0 to <= 0 inside (a.s, b.s): the curve becomes followable where a braking
  // profile touches it tangentially. Bisection; corners between scan points are concave (the
  // curve is a minimum of smooth curves) and only raise g, so the crossing found is a real one.
  std::optional<SwitchingPoint> between(int piece, Probe a, Probe b) const {
    for (int i = 0; i < 60 && b.s - a.s > eps_; ++i) {
      const Probe m = probe(piece, 0.5 * (a.s + b.s), Side::both);
      (m.g > 0 ? a : b) = m;
    }
    if (!eligible(b.s)) return std::nullopt;
    return SwitchingPoint{b.s, lim_.max_u(piece, b.s)};
  }

  bool eligible(double s) const { return s >= from_ && s > after_ + eps_; }

  const PhaseLimits& lim_;
  const BlendedPath& path_;
  const double from_, after_, eps_;
  std::optional<Probe> prev_;
};

}  // namespace

std::optional<SwitchingPoint> next_switching_point(const PhaseLimits& limits, double from, double after) {
  return Scanner(limits, from, after).run();
}

}  // namespace dmgplace::runtime::detail
