// Forward kinematics of 8 configurations at once (Kinematics::Lanes): every step runs in SIMD
// lanes (lanes.hpp vectors, sincos as a loop the compiler vectorises); compiled twice, for AVX2 +
// FMA and for the portable x86-64 baseline, and chosen at run time (system/simd_dispatch).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <type_traits>

#include "dmgplace/runtime/geometry/fast_sincos.hpp"
#include "dmgplace/runtime/robot/kinematics_lanes.hpp"
#include "dmgplace/runtime/system/lanes.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {
namespace {

constexpr int N = LinkPoseLanesD::kLanes;

using JointPlan = Kinematics::Lanes::Joint;

// sin and cos of every lane (fast_sincos' branch-free core); lanes beyond +-1e5 rad take libm.
inline __attribute__((always_inline)) void sincos_lanes(const double* x, double* s, double* c) {
  bool wild = false;
  for (int k = 0; k < N; ++k) wild |= !(std::abs(x[k]) < 1e5);
  if (wild) {
    for (int k = 0; k < N; ++k) fast_sincos(x[k], s[k], c[k]);
    return;
  }
  for (int k = 0; k < N; ++k) fast_sincos_core(x[k], s[k], c[k]);
}

// The same in floats (fast_sincos_f8: the reduction in doubles, the polynomials in floats); wild
// lanes take the double answer, rounded.
// Compiled for AVX2 only (the portable build keeps the double core), so the range test is two
// vector compares and one mask.
inline __attribute__((always_inline)) void sincos_lanes_f(const double* x, float* s, float* c) {
  const lanes::D lim = lanes::splat(1e5);
  const lanes::M tame = (lanes::abs(lanes::load(x)) < lim) & (lanes::abs(lanes::load(x + 4)) < lim);  // NaN: not
  if (lanes::bits(tame, true) == 0xF) return fast_sincos_f8(x, s, c);
  for (int k = 0; k < N; ++k) {
    double sd, cd;
    fast_sincos(x[k], sd, cd);
    s[k] = float(sd), c[k] = float(cd);
  }
}

// A joint constant in every lane of T's vector: doubles as an initialiser list, floats as
// lanes::splatf's shuffle (lanes.hpp: each is the faster form for its kind).
template <class T>
DMGPLACE_LANES_INLINE lanes::VectorOf<T> splat_as(double v) {
  if constexpr (std::is_same_v<T, double>) return lanes::splat(v);
  else return lanes::splatf(float(v));
}

// The joint's value in every lane, into vd. AVX2: built in registers and stored a whole vector at
// a time; stored lane by lane, sincos' vector loads of them waited on failed store forwarding. The
// portable build keeps the lane loop: there the vectors were slower.
template <bool Wide>
DMGPLACE_LANES_INLINE void joint_values(const JointPlan& j, const double* const* q, double* vd) {
  if constexpr (Wide) {
    for (int h = 0; h < N; h += lanes::W) {
      lanes::D x = lanes::splat(j.offset);
      if (j.slot >= 0) {
        const int at = j.slot;
        x += lanes::splat(j.mult) * lanes::D{q[h][at], q[h + 1][at], q[h + 2][at], q[h + 3][at]};
      }
      lanes::store(vd + h, x);
    }
  } else {
    for (int k = 0; k < N; ++k) vd[k] = j.slot >= 0 ? j.mult * q[k][j.slot] + j.offset : j.offset;
  }
}

// What the joint's transform needs of its values: sin and cos (revolute) or the value (prismatic)
// in T, from the doubles vd (into sd/cd, then sf/cf/vf rounded once, for floats).
template <class T, bool Wide>
DMGPLACE_LANES_INLINE void joint_terms(const JointPlan& j, const double* vd, double* sd, double* cd, T* sf, T* cf,
                                       T* vf) {
  if constexpr (std::is_same_v<T, double>) {
    if (j.type == 1) sincos_lanes(vd, sd, cd);
  } else if (j.type == 1) {
    // The portable build keeps the double core, rounded: its float vectors are SSE pairs, and
    // fast_sincos_f8 there made the float lanes slower.
    if constexpr (Wide) {
      sincos_lanes_f(vd, sf, cf);
    } else {
      sincos_lanes(vd, sd, cd);
      for (int k = 0; k < N; ++k) sf[k] = T(sd[k]), cf[k] = T(cd[k]);
    }
  } else if (j.type == 2) {
    for (int k = 0; k < N; ++k) vf[k] = T(vd[k]);
  }
}

// Child pose = parent pose x the joint's transform at its values (v, s, c), W lanes at a time.
template <class T, class Pose>
DMGPLACE_LANES_INLINE void compose_joint(const JointPlan& j, const Pose& A, Pose& C, const T* v, const T* s,
                                         const T* c) {
  using D = lanes::VectorOf<T>;
  constexpr int W = int(sizeof(D) / sizeof(T));
  static_assert(N % W == 0);
  auto splat = [](double x) __attribute__((always_inline)) { return splat_as<T>(x); };
  const D t0 = splat(j.t[0]), t1 = splat(j.t[1]), t2 = splat(j.t[2]);
  for (int h = 0; h < N; h += W) {
    auto a = [&](int e) __attribute__((always_inline)) { return lanes::load(A[std::size_t(e)].data() + h); };
    auto put = [&](int e, D x) __attribute__((always_inline)) { lanes::store(C[std::size_t(e)].data() + h, x); };
    // Translation: parent R (t + v a) + parent t.
    D tx = t0, ty = t1, tz = t2;
    if (j.type == 2) {
      const D m = lanes::load(v + h);
      tx += m * splat(j.a[0]), ty += m * splat(j.a[1]), tz += m * splat(j.a[2]);
    }
    for (int r = 0; r < 3; ++r) put(9 + r, a(3 * r) * tx + a(3 * r + 1) * ty + a(3 * r + 2) * tz + a(9 + r));
    if (j.quarter) {
      // The parent's columns permuted (a quarter-turn origin); a revolute joint then turns the
      // two columns across its axis: (u, w) -> (c u + s w, c w - s u). Kinematics::compose.
      const int ia = (j.axis + 1) % 3, ib = (j.axis + 2) % 3;
      const D sg0 = splat(j.sign[0]), sg1 = splat(j.sign[1]), sg2 = splat(j.sign[2]);
      for (int r = 0; r < 3; ++r) {
        D x[3] = {sg0 * a(3 * r + j.perm[0]), sg1 * a(3 * r + j.perm[1]), sg2 * a(3 * r + j.perm[2])};
        if (j.type == 1) {
          const D ck = lanes::load(c + h), sk = splat(j.axis_sign) * lanes::load(s + h);
          const D u = x[ia], w = x[ib];
          x[ia] = ck * u + sk * w;
          x[ib] = ck * w - sk * u;
        }
        for (int col = 0; col < 3; ++col) put(3 * r + col, x[col]);
      }
      continue;
    }
    // The joint's rotation (origin, then Rodrigues about the axis), then parent R x it.
    D R[9];
    if (j.type == 1) {
      const D sk = lanes::load(s + h), ck = splat(1.0) - lanes::load(c + h);
      for (int e = 0; e < 9; ++e) R[e] = splat(j.O[e]) + sk * splat(j.OK[e]) + ck * splat(j.OKK[e]);
    } else {
      for (int e = 0; e < 9; ++e) R[e] = splat(j.O[e]);
    }
    for (int r = 0; r < 3; ++r) {
      const D p0 = a(3 * r), p1 = a(3 * r + 1), p2 = a(3 * r + 2);
      for (int col = 0; col < 3; ++col) put(3 * r + col, p0 * R[col] + p1 * R[3 + col] + p2 * R[6 + col]);
    }
  }
}

// Every link expressed in the base frame: pose = inverse(base) x pose, per lane.
template <class T>
DMGPLACE_LANES_INLINE void to_base_frame(LinkPoseLanes<T>& out, int base) {
  auto& P = out.pose;
  alignas(64) T Bi[12][N];
  const auto& B = P[std::size_t(base)];
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col)
      for (int k = 0; k < N; ++k) Bi[3 * r + col][k] = B[std::size_t(3 * col + r)][std::size_t(k)];  // transpose
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < N; ++k)
      Bi[9 + r][k] = -(Bi[3 * r][k] * B[9][std::size_t(k)] + Bi[3 * r + 1][k] * B[10][std::size_t(k)] +
                       Bi[3 * r + 2][k] * B[11][std::size_t(k)]);
  alignas(64) T X[12][N];
  for (auto& L : P) {
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 4; ++col)
        for (int k = 0; k < N; ++k) {
          const int e = col < 3 ? 3 * r + col : 9 + r;
          const int x = col < 3 ? col : 9;  // column col of L's rotation, or its translation
          const T dot = Bi[3 * r][k] * L[std::size_t(col < 3 ? x : 9)][std::size_t(k)] +
                        Bi[3 * r + 1][k] * L[std::size_t(col < 3 ? 3 + x : 10)][std::size_t(k)] +
                        Bi[3 * r + 2][k] * L[std::size_t(col < 3 ? 6 + x : 11)][std::size_t(k)];
          X[e][k] = dot + (col < 3 ? T(0) : Bi[9 + r][k]);
        }
    for (int e = 0; e < 12; ++e)
      for (int k = 0; k < N; ++k) L[std::size_t(e)][std::size_t(k)] = X[e][k];
  }
}

// T = double: two vectors of 4 lanes per step. T = float: one vector of all 8 (the joint values
// in doubles, sin and cos from them by fast_sincos_f8, a prismatic joint's value rounded once).
// Wide: compiled for AVX2. Every step is written in lanes.hpp vectors (doubles: half the lanes at
// a time), with the joint's constants splatted into registers: as plain loops over lanes GCC kept
// some scalar (it cannot tell the child's stores from the plan's constants).
template <class T, bool Wide>
inline __attribute__((always_inline)) void fk_body(const std::vector<JointPlan>& plan, const std::vector<int>& roots,
                                                   int base, bool base_is_root, const double* const* q,
                                                   LinkPoseLanes<T>& out) {
  auto& P = out.pose;
  for (int r : roots)
    for (int e = 0; e < 12; ++e) P[std::size_t(r)][std::size_t(e)].fill(e == 0 || e == 4 || e == 8 ? 1.0 : 0.0);
  alignas(64) double vd[N], sd[N], cd[N];
  alignas(64) T vf[N], sf[N], cf[N];  // floats: the doubles rounded once
  const T *v = vf, *s = sf, *c = cf;
  if constexpr (std::is_same_v<T, double>) v = vd, s = sd, c = cd;
  for (const JointPlan& j : plan) {
    joint_values<Wide>(j, q, vd);
    joint_terms<T, Wide>(j, vd, sd, cd, sf, cf, vf);
    compose_joint<T>(j, P[std::size_t(j.parent)], P[std::size_t(j.child)], v, s, c);
  }
  if (!base_is_root) to_base_frame(out, base);
}

template <class T>
__attribute__((target("avx2,fma"))) void fk_avx2(const std::vector<JointPlan>& plan, const std::vector<int>& roots,
                                                 int base, bool base_is_root, const double* const* q,
                                                 LinkPoseLanes<T>& out) {
  fk_body<T, true>(plan, roots, base, base_is_root, q, out);
}

template <class T>
void fk_portable(const std::vector<JointPlan>& plan, const std::vector<int>& roots, int base, bool base_is_root,
                 const double* const* q, LinkPoseLanes<T>& out) {
  fk_body<T, false>(plan, roots, base, base_is_root, q, out);
}

template <class T>
void fk(const std::vector<JointPlan>& plan, const std::vector<int>& roots, int base, bool base_is_root,
        const double* const* q, std::size_t links, LinkPoseLanes<T>& out) {
  out.pose.resize(links);
  if (simd_path() == SimdPath::Avx2) fk_avx2(plan, roots, base, base_is_root, q, out);
  else fk_portable(plan, roots, base, base_is_root, q, out);
}

}  // namespace

Kinematics::Lanes::Lanes(const Kinematics& kin)
    : roots_(kin.roots_), base_(kin.base_), base_is_root_(kin.base_is_root_), links_(kin.model_->links.size()) {
  build_plan(kin);
  bound_float_error(kin);
  build_frames();
}

void Kinematics::Lanes::build_plan(const Kinematics& kin) {
  const auto& m = *kin.model_;
  plan_.assign(kin.order_.size(), {});
  for (std::size_t i = 0; i < kin.order_.size(); ++i) {
    const int j = kin.order_[i];
    const auto& jt = m.joints[std::size_t(j)];
    Joint& p = plan_[i];
    p.type = jt.type == JointType::Fixed ? 0 : jt.type == JointType::Prismatic ? 2 : 1;
    p.parent = jt.parent;
    p.child = jt.child;
    // Resolve mimic chains to one driving joint: value = mult * driver + offset.
    int d = j;
    while (m.joints[std::size_t(d)].mimic >= 0) {
      const auto& mj = m.joints[std::size_t(d)];
      p.offset += p.mult * mj.mimic_offset;
      p.mult *= mj.mimic_multiplier;
      d = mj.mimic;
    }
    p.slot = kin.chain_slot_[std::size_t(d)];
    if (p.slot < 0) p.offset += p.mult * kin.fixed_values_[std::size_t(d)], p.mult = 0;
    const Eigen::Matrix3d O = jt.origin.linear();
    const auto& terms = kin.terms_[std::size_t(j)];
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) {
        p.O[3 * r + col] = O(r, col);
        p.OK[3 * r + col] = terms.OK(r, col);
        p.OKK[3 * r + col] = terms.OKK(r, col);
      }
    for (int r = 0; r < 3; ++r) p.t[r] = jt.origin.translation()[r], p.a[r] = terms.Oa[r];
    p.quarter = terms.quarter;
    p.axis = terms.axis;
    p.axis_sign = terms.axis_sign;
    for (int c = 0; c < 3; ++c) p.perm[c] = terms.perm[c], p.sign[c] = terms.sign[c];
  }
}

// Float forward kinematics' error, link by link down the plan (u = 2^-24, a float's unit roundoff;
// |.| Frobenius norms of error matrices, so a rotation multiplies them by 1). A revolute joint's
// rotation O + s OK + (1 - c) OKK (|O| = sqrt 3, |OK| = |OKK| = sqrt 2): the constants rounded
// (under 6u with |s| <= 1, |1 - c| <= 2), sin and cos off by E = kSincosF8Error each and 1 - c
// rounded (sqrt 2 (2E + 2u)), two fused multiply-adds rounding sums under 3.2 and 1.8 (5u): under
// 14u + 3E. (The portable build rounds the two products too, 4.3u more, but its sin and cos are
// the double core's rounded once, E under u: less in all. A quarter-turn joint turns two columns
// in place, c u + s w: less.) A fixed joint's
// rounded constants: under 3u. The child's R = A Rj in floats: |E_child| <= |E_A| + |E_Rj| + 9u
// (each element three roundings of partial sums under 2). Its translation A t' + t_A: off by
// |E_A| |t'| from A's error, 5u |t'| from rounding t' and the dots, u |t_child| from the sum.
// Composing with the base's inverse, when the base is not the root, adds as much again. The lane
// frames' plan (frame_poses) composes a subset: a chain joint below links fixed to their
// parents has their offsets folded into its constants, rounded once, with |t'| no more than the
// sum of the translations it replaces: the same bound holds.
void Kinematics::Lanes::bound_float_error(const Kinematics& kin) {
  const double u = 0x1p-24;
  const auto& m = *kin.model_;
  std::vector<double> rot(m.links.size(), 0.0), trans(m.links.size(), 0.0), extent(m.links.size(), 0.0);
  for (const Joint& j : plan_) {
    double travel = std::abs(j.offset);
    if (j.slot >= 0) travel += std::abs(j.mult) * std::max(std::abs(kin.lower_[j.slot]), std::abs(kin.upper_[j.slot]));
    const double t = std::hypot(j.t[0], j.t[1], j.t[2]) + (j.type == 2 ? travel : 0.0);
    const auto a = std::size_t(j.parent), c = std::size_t(j.child);
    rot[c] = rot[a] + (j.type == 0 ? 3 * u : (14 + 3 * kSincosF8Error) * u) + 9 * u;
    extent[c] = extent[a] + t;
    trans[c] = trans[a] + rot[a] * t + 5 * u * t + u * extent[c];
  }
  const auto b = std::size_t(base_);
  float_rotation_error_ = float_translation_error_ = 0;
  for (std::size_t l = 0; l < m.links.size(); ++l) {
    double r = rot[l], e = trans[l];
    if (!base_is_root_) {
      r += rot[b] + 9 * u;
      e += trans[b] + (rot[b] + 5 * u) * (extent[l] + extent[b]) + u * (extent[l] + extent[b]);
    }
    float_rotation_error_ = std::max(float_rotation_error_, r);
    float_translation_error_ = std::max(float_translation_error_, e);
  }
}

double Kinematics::Lanes::float_pose_error(double reach) const {
  // R p + t in floats: |E_R| |p| from the rotation, 4u |p| from rounding p and the dots, and the
  // translation's error; u of the result's magnitude is inside the callers' own margins.
  return (float_rotation_error_ + 4 * 0x1p-24) * reach + float_translation_error_;
}

void Kinematics::Lanes::link_poses(const double* const* q, LinkPoseLanesD& out) const {
  fk(plan_, roots_, base_, base_is_root_, q, links_, out);
}

void Kinematics::Lanes::link_poses(const double* const* q, LinkPoseLanesF& out) const {
  fk(plan_, roots_, base_, base_is_root_, q, links_, out);
}

void Kinematics::Lanes::frame_poses(const double* const* q, LinkPoseLanesF& out) const {
  fk(frame_plan_, roots_, base_, base_is_root_, q, links_, out);
}

// A joint the chain does not drive (fixed, or set outside the chain) carries its child rigidly
// with its parent: the child joins the parent's frame, at the parent's offset composed with the
// joint at its value. Only when the base is the root: poses are then the root-relative ones FK
// composes, and the base's own pose is not needed to re-express them.
void Kinematics::Lanes::build_frames() {
  using Rows = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;  // Joint's row-major arrays
  using Vec = Eigen::Map<Eigen::Vector3d>;
  static std::atomic<std::uint64_t> versions{0};
  version = ++versions;
  const std::size_t n = links_;
  frame_of_.resize(n);
  for (std::size_t l = 0; l < n; ++l) frame_of_[l] = int(l);
  frame_offset_.assign(n, Eigen::Isometry3d::Identity());
  frame_plan_.clear();
  for (Joint f : plan_) {
    const auto parent = std::size_t(f.parent);
    if (base_is_root_ && (f.type == 0 || f.slot < 0)) {
      // Its value is f.offset (no slot): the plan's own rotation and translation terms at it.
      const double v = f.offset;
      Eigen::Isometry3d joint = Eigen::Isometry3d::Identity();
      joint.linear() = Rows(f.O);
      if (f.type == 1) joint.linear() += std::sin(v) * Rows(f.OK) + (1 - std::cos(v)) * Rows(f.OKK);
      joint.translation() = Vec(f.t);
      if (f.type == 2) joint.translation() += v * Vec(f.a);
      frame_of_[std::size_t(f.child)] = frame_of_[parent];
      frame_offset_[std::size_t(f.child)] = frame_offset_[parent] * joint;
      continue;
    }
    if (frame_of_[parent] != f.parent) {
      // A chain joint below links it would carry hangs off their frame, its origin carried there.
      const Eigen::Isometry3d& F = frame_offset_[parent];
      const Eigen::Matrix3d R = F.linear();
      f.parent = frame_of_[parent];
      Rows(f.O) = R * Rows(f.O);
      Rows(f.OK) = R * Rows(f.OK);
      Rows(f.OKK) = R * Rows(f.OKK);
      Vec(f.t) = R * Vec(f.t) + F.translation();
      Vec(f.a) = R * Vec(f.a);
      if (R != Eigen::Matrix3d::Identity()) f.quarter = false;  // O is no longer a signed permutation
    }
    frame_plan_.push_back(f);
  }
}

}  // namespace dmgplace::runtime
