#pragma once
// How far a body's bounding ball, or a pair's two relative to each other, can move over a span
// lane check's reach, lane by lane (SphereFieldChecker::free_lanes_along): the three bounds of
// displacement_bound.hpp (static, Gronwall, Taylor) as BallMotion sums them, each evaluated at the
// reach t itself, in float lanes from the lane check's float poses. The static bound alone (the chain
// reaches) assumes every joint at its farthest; the lanes' own lever arms, and joint motions that
// cancel, make it several times smaller near obstacles, so fewer lanes fail and fewer stretches
// go to certified checks. Private to the runtime.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dmgplace/runtime/collision/kernels/lane_points.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/system/lanes.hpp"

namespace dmgplace::runtime {

struct SphereFieldChecker::LaneMotion {
  using F = lanes::F;
  const double* dir = nullptr;  // the unit joint-space direction, by slot
  double t = 0;                 // the reach: joint-space length either way
  // Float rounding: axis_error bounds a joint axis's error (its unit vector), point_error twice a
  // point's (a body center and a joint origin: lane_margin()).
  float axis_error = 0, point_error = 0;
  // Scratch per lane check, filled on first use: per slot, the joint's axis and a point on it in the
  // world; per body (lever_begin), each chain joint's lever arm about the body center, its norm
  // plus rounding, and that rounding.
  LaneXyz *axis = nullptr, *origin = nullptr, *arm = nullptr;
  std::array<float, LinkPoseLanesD::kLanes>* arm_norm = nullptr;
  std::array<float, LinkPoseLanesD::kLanes>* arm_error = nullptr;
  char *slot_done = nullptr, *body_done = nullptr;

  // A LaneMotion for one lane check of `c` along `direction` over `reach`, on this thread's scratch.
  static LaneMotion start(const SphereFieldChecker& c, const Eigen::VectorXd& direction, double reach) {
    struct Scratch {
      std::vector<LaneXyz> axis, origin, arm;
      std::vector<std::array<float, LinkPoseLanesD::kLanes>> arm_norm, arm_error;
      std::vector<char> slot_done, body_done;
    };
    thread_local Scratch s;
    const auto slots = std::size_t(c.kin_->dof()), levers = std::size_t(c.lever_count_);
    s.axis.resize(slots);
    s.origin.resize(slots);
    s.arm.resize(levers);
    s.arm_norm.resize(levers);
    s.arm_error.resize(levers);
    s.slot_done.assign(slots, 0);
    s.body_done.assign(c.bodies_.size(), 0);
    LaneMotion m;
    m.dir = direction.data();
    m.t = reach;
    m.axis_error = float(c.kin_->lanes().float_pose_error(1.0) + 1e-6);
    m.point_error = float(2 * c.lane_margin());
    m.axis = s.axis.data();
    m.origin = s.origin.data();
    m.arm = s.arm.data();
    m.arm_norm = s.arm_norm.data();
    m.arm_error = s.arm_error.data();
    m.slot_done = s.slot_done.data();
    m.body_done = s.body_done.data();
    return m;
  }

  // How far the reach can move a self-distance table's bound (Table::speed over t), rounded up.
  // No lanes: the travel is the same for all.
  double table_travel(const Table& table) const { return table.speed(dir) * t * (1 + 1e-9); }

  // The largest displacement of body bi's bounding ball over [-t, t] along dir, over the lanes in
  // `lanes`, rounded up; NaN where a lane's geometry is not finite (the caller keeps its static
  // bound then). `center`: every body's center in every lane.
  DMGPLACE_LANES_INLINE float body(const SphereFieldChecker& c, std::size_t bi, const LinkPoseLanesF& poses,
                                   const LaneXyz* center, std::uint32_t lanes) const {
    const Body& b = c.bodies_[bi];
    Sums s;
    ball(c, bi, poses, center, b.chain, nullptr, s);
    return farthest(s, lanes);
  }
  // The same for pair pi: how far its two balls can move relative to each other (PairMoves).
  DMGPLACE_LANES_INLINE float pair(const SphereFieldChecker& c, std::size_t pi, const LinkPoseLanesF& poses,
                                   const LaneXyz* center, std::uint32_t lanes) const {
    const Pair& p = c.pairs_[pi];
    const PairMoves& m = c.pair_moves_[pi];
    Sums s;
    ball(c, std::size_t(p.a), poses, center, m.a, m.a_at.data(), s);
    Sums sb;
    ball(c, std::size_t(p.b), poses, center, m.b, m.b_at.data(), sb);
    // DisplacementBound::add: sums bound the sum, the larger turn rate serves both.
    s.v0 += sb.v0;
    s.second += sb.second;
    s.first += sb.first;
    s.reach_speed += sb.reach_speed;
    s.turn = std::max(s.turn, sb.turn);
    return farthest(s, lanes);
  }

 private:
  struct Sums {
    F v0{}, second{}, first{};  // local speed, second order, first order (rounding included)
    double turn = 0, reach_speed = 0;
  };

  // BallMotion's sums (displacement_bound.cpp) for body bi's ball moved by `joints` (its chain,
  // or a subset in chain order; `at`: their places in the chain, null for the whole chain), added
  // to s.
  DMGPLACE_LANES_INLINE void ball(const SphereFieldChecker& c, std::size_t bi, const LinkPoseLanesF& poses,
                                  const LaneXyz* center, const std::vector<ChainJoint>& joints, const int* at,
                                  Sums& s) const {
    levers(c, bi, poses, center);
    const Body& b = c.bodies_[bi];
    const F radius = lanes::splatf(float(b.radius));
    F lx{}, ly{}, lz{}, wx{}, wy{}, wz{}, lin_err{};
    double frame_turn = 0, ang_err = 0;
    for (auto k = joints.size(); k-- > 0;) {  // from the top of the chain down
      const ChainJoint& j = joints[k];
      const double u = dir[j.slot], au = std::abs(u);
      s.reach_speed += au * j.reach;
      const LaneXyz& a = axis[std::size_t(j.slot)];
      const F ax = lanes::load(a.x), ay = lanes::load(a.y), az = lanes::load(a.z), uu = lanes::splatf(float(u)),
              auf = lanes::splatf(float(au));
      ang_err += au * axis_error;
      if (j.prismatic) {
        lx += uu * ax;
        ly += uu * ay;
        lz += uu * az;
        lin_err += lanes::splatf(float(au * axis_error));
        s.v0 += auf;
        s.second += lanes::splatf(float(au * frame_turn));
        continue;
      }
      frame_turn += au;
      const auto e = std::size_t(b.lever_begin + (at ? at[k] : int(k)));
      const F r = lanes::load(arm_norm[e].data()) + radius;
      lx += uu * lanes::load(arm[e].x);
      ly += uu * lanes::load(arm[e].y);
      lz += uu * lanes::load(arm[e].z);
      wx += uu * ax;
      wy += uu * ay;
      wz += uu * az;
      lin_err += auf * lanes::load(arm_error[e].data());
      s.v0 += auf * r;
      s.second += lanes::splatf(float(au * frame_turn)) * r;
    }
    s.turn = std::max(s.turn, frame_turn);
    // First order: |v(c)| + |omega| R, each with its rounding.
    s.first += lanes::sqrt(lx * lx + ly * ly + lz * lz) + lin_err +
               (lanes::sqrt(wx * wx + wy * wy + wz * wz) + lanes::splatf(float(ang_err))) * radius;
  }

  // The smallest of the three bounds at t, over `lanes`.
  DMGPLACE_LANES_INLINE float farthest(const Sums& s, std::uint32_t lanes) const {
    using lanes::splatf;
    // Gronwall's V0 / W (exp(W t) - 1) and the Taylor remainder's V0 / W (exp(W t) - 1 - W t) as
    // V0 times factors the lanes share (W does not depend on them), in doubles, rounded up.
    double g1 = t, g2 = 0;
    if (s.turn > 1e-12) {
      const double x = s.turn * t;
      g1 = std::expm1(x) / s.turn;
      // e^x - 1 - x <= x^2 / 2 (1 + x e^x / 3): no cancellation for small x.
      g2 = x < 1e-3 ? 0.5 * s.turn * t * t * (1 + x * 0.34) : (std::expm1(x) - x) / s.turn;
    }
    const F gronwall = s.v0 * splatf(float(g1 * (1 + 1e-6)));
    const F taylor =
        s.first * splatf(float(t)) + s.second * splatf(float(0.5 * t * t)) + s.v0 * splatf(float(g2 * (1 + 1e-6)));
    const F d = lanes::min(lanes::min(gronwall, taylor), splatf(float(s.reach_speed * t))) * splatf(1 + 1e-5f);
    alignas(32) float out[LinkPoseLanesD::kLanes];
    lanes::store(out, d);
    float most = 0;
    for (int k = 0; k < LinkPoseLanesD::kLanes; ++k)
      if (lanes >> k & 1u) {
        if (!std::isfinite(out[k])) return std::nanf("");
        most = std::max(most, out[k]);
      }
    return most;
  }

  // Body bi's lever arms about its chain's revolute joints, every lane, once per lane check.
  DMGPLACE_LANES_INLINE void levers(const SphereFieldChecker& c, std::size_t bi, const LinkPoseLanesF& poses,
                                    const LaneXyz* center) const {
    if (body_done[bi]) return;
    body_done[bi] = 1;
    const Body& b = c.bodies_[bi];
    const F cx = lanes::load(center[bi].x), cy = lanes::load(center[bi].y), cz = lanes::load(center[bi].z);
    for (std::size_t k = 0; k < b.chain.size(); ++k) {
      const ChainJoint& j = b.chain[k];
      joint(j, poses);
      if (j.prismatic) continue;
      const LaneXyz &a = axis[std::size_t(j.slot)], &o = origin[std::size_t(j.slot)];
      const F ax = lanes::load(a.x), ay = lanes::load(a.y), az = lanes::load(a.z);
      const F dx = cx - lanes::load(o.x), dy = cy - lanes::load(o.y), dz = cz - lanes::load(o.z);
      const F mx = ay * dz - az * dy, my = az * dx - ax * dz, mz = ax * dy - ay * dx;
      // Its error: the axis's times |d| (|d| <= its L1 norm), the cross product's rounding, and
      // the two points'.
      const F err = lanes::splatf(axis_error + 1e-6f) * (lanes::abs(dx) + lanes::abs(dy) + lanes::abs(dz)) +
                    lanes::splatf(point_error);
      const auto e = std::size_t(b.lever_begin) + k;
      lanes::store(arm[e].x, mx);
      lanes::store(arm[e].y, my);
      lanes::store(arm[e].z, mz);
      lanes::store(arm_norm[e].data(), lanes::sqrt(mx * mx + my * my + mz * mz) + err);
      lanes::store(arm_error[e].data(), err);
    }
  }

  // Joint j's axis and origin in the world, every lane: its child link's pose applied to the axis
  // it holds at its origin.
  DMGPLACE_LANES_INLINE void joint(const ChainJoint& j, const LinkPoseLanesF& poses) const {
    const auto slot = std::size_t(j.slot);
    if (slot_done[slot]) return;
    slot_done[slot] = 1;
    const auto& T = poses.pose[std::size_t(j.child)];
    auto e = [&](int i) __attribute__((always_inline)) { return lanes::load(T[std::size_t(i)].data()); };
    const F x = lanes::splatf(float(j.axis.x())), y = lanes::splatf(float(j.axis.y())),
            z = lanes::splatf(float(j.axis.z()));
    lanes::store(axis[slot].x, e(0) * x + e(1) * y + e(2) * z);
    lanes::store(axis[slot].y, e(3) * x + e(4) * y + e(5) * z);
    lanes::store(axis[slot].z, e(6) * x + e(7) * y + e(8) * z);
    lanes::store(origin[slot].x, e(9));
    lanes::store(origin[slot].y, e(10));
    lanes::store(origin[slot].z, e(11));
  }
};

}  // namespace dmgplace::runtime
