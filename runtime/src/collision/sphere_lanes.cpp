// SphereFieldChecker::free_lanes: the fast layer's "proven free" for 8 configurations at once.
// Every step runs in floats across all 8 lanes (lanes::F, one AVX register): forward kinematics
// (Kinematics::frame_poses_lanes into a LinkPoseLanesF, the bodies carried into their lane frames),
// then one body or sphere at a time: centers, bounds, exact primitive distances, pair distances.
// Every test that can say "free" adds a rounding margin (lane_margin(): the kinematics' own error
// bound and the steps after it; a pair test adds a second pose error, one per body), so the
// floats stay conservative. Only the field loads are one per lane. Compiled for AVX2 + FMA and
// for the portable baseline, chosen at run time (system/simd_dispatch).
#include <algorithm>
#include <array>
#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/collision/kernels/table_lookup.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/system/lanes.hpp"
#include "sphere_lane_motion.hpp"
#include "sphere_lane_pass.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::runtime {
namespace {

constexpr int N = LinkPoseLanesD::kLanes;

}  // namespace

// Table::lower_bound for 8 configurations (kernels/table_lookup.hpp).
inline __attribute__((always_inline)) std::uint32_t SphereFieldChecker::Table::apart_lanes(const double* const* q,
                                                                                           double padding,
                                                                                           bool wide) const {
  return kernels::table_apart({slot, data.lower, data.step, inv_step, data.slope, data.count, tenths_mm.data()}, q,
                              padding, wide);
}

void SphereFieldChecker::set_lane_bounds() {
  const double scene =
      std::max({2.0, lo_.cwiseAbs().maxCoeff(), hi_.cwiseAbs().maxCoeff(), obstacles_ ? obstacles_->extent() : 0.0});
  lane_limit_ = std::max(scene, reach_);
  // Every float step rounds by at most 2^-24 of the magnitudes it meets: coordinates up to
  // lane_limit_ (body centers past it drop their lane), sphere offsets within reach_, primitive
  // extents. A pose element, a transform, a difference, a rotation into a primitive's frame and a
  // squared distance each add a few such roundings; 64 of them bound the lot with room to spare.
  // Forward kinematics in floats adds its own bound, for points as far from their link's origin
  // as any sphere's far side.
  lane_rounding_ = 64.0 * 0x1p-24 * (lane_limit_ + 2.0 * reach_ + 1.0);
  // |p - from| <= 2 (lane_limit_ + reach_) and |d| <= 2 reach_ there (every point of a body is
  // within reach_ of its center).
  capsule_rounding_ = kernels::kSegmentRounding * 0x1p-24 * (2.0 * lane_limit_ + 4.0 * reach_ + 1.0);
  exact_float_error_ = obstacles_ ? obstacles_->float_error(lane_limit_) : 0.0;
}

double SphereFieldChecker::lane_margin() const {
  // The kinematics' float error bound as it is now: setting a joint outside the chain
  // (Kinematics::set_joint_value) rebuilds it, so it is asked per lane check, not kept.
  return lane_rounding_ + kin_->lanes().float_pose_error(link_reach_);
}

void SphereFieldChecker::set_exact_obstacles(std::shared_ptr<const PrimitiveObstacles> obstacles) {
  if (!fine_ && (!obstacles || !obstacles->all_have_bits()))
    throw Error("SphereFieldChecker", "scene", "a checker without a distance field needs at most 64 exact primitives");
  obstacles_ = std::move(obstacles);
  set_lane_bounds();
}

// The environment pass, then the self pairs (sphere_lane_pass.hpp), on 8 configurations.
inline __attribute__((always_inline)) std::uint32_t SphereFieldChecker::free_lanes_body(const SphereFieldChecker& c,
                                                                                        const double* const* q,
                                                                                        int count, const float* widen,
                                                                                        const LaneMotion* motion,
                                                                                        bool wide) {
  LanePass p(c, q, count, widen, motion, wide);
  if (!p.environment()) return 0;
  if (!p.self_pairs()) return 0;
  return p.alive & p.all;
}

// flatten: lanes::movemask_avx (AVX only, so not always_inline) is inlined here too; left to the
// inliner, this function is past its size limits and each mask became a call.
__attribute__((target("avx2,fma"), flatten)) std::uint32_t SphereFieldChecker::free_lanes_avx2(
    const SphereFieldChecker& c, const double* const* q, int count, const float* widen, const LaneMotion* motion) {
  return free_lanes_body(c, q, count, widen, motion, true);
}

std::uint32_t SphereFieldChecker::free_lanes_portable(const SphereFieldChecker& c, const double* const* q, int count,
                                                      const float* widen, const LaneMotion* motion) {
  return free_lanes_body(c, q, count, widen, motion, false);
}

std::uint32_t SphereFieldChecker::free_lanes(const double* const* q, int count) const {
  if (count <= 0) return 0;
  count = std::min(count, N);
  return simd_path() == SimdPath::Avx2 ? free_lanes_avx2(*this, q, count, nullptr, nullptr)
                                       : free_lanes_portable(*this, q, count, nullptr, nullptr);
}

}  // namespace dmgplace::runtime
