// SphereFieldChecker::free_lanes_along: span lane checks, each lane proving every configuration within
// a reach of it along a direction. Each body's (each pair's) tests are widened by how far it can
// move over the reach: first by the static bound (the chain reaches), then, where that leaves a
// test undecided, by the lanes' own (sphere_lane_motion.hpp) inside the kernel (sphere_lanes.cpp).
#include <algorithm>
#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/collision/sphere_field_checker.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"
#include "sphere_lane_motion.hpp"

namespace dmgplace::runtime {

const std::vector<double>& SphereFieldChecker::static_speeds(const Eigen::VectorXd& direction) const {
  struct Last {
    std::uint64_t id = 0;
    std::vector<double> direction, speeds;
    Eigen::VectorXd magnitude;  // |direction|, kept so the product allocates nothing
  };
  thread_local Last last;
  const auto n = std::size_t(direction.size());
  if (last.id == id_ && last.direction.size() == n &&
      std::equal(last.direction.begin(), last.direction.end(), direction.data()))
    return last.speeds;
  if (direction.size() != static_reach_.cols())
    throw Error("SphereFieldChecker", "direction", "one entry per chain joint expected");
  // Each row: the sum over its joints of |direction| x reach (one matrix-vector product).
  last.magnitude = direction.cwiseAbs();
  last.speeds.resize(std::size_t(static_reach_.rows()));
  Eigen::Map<Eigen::VectorXd>(last.speeds.data(), static_reach_.rows()).noalias() = static_reach_ * last.magnitude;
  last.id = id_;
  last.direction.assign(direction.data(), direction.data() + n);
  return last.speeds;
}

bool SphereFieldChecker::static_widening(const Eigen::VectorXd& direction, double reach,
                                         std::vector<float>& widen) const {
  // How far each body (then each pair, relative to each other) can move over `reach` along
  // +-direction: the static bound of check_along's first cut, rounded up into floats.
  widen.clear();
  for (const double v : static_speeds(direction)) {
    const double w = reach * v * (1 + 0x1p-20);
    if (!(w <= 1.0)) return false;  // past the magnitudes lane_margin() covers; nothing that far is proven
    widen.push_back(float(w));
  }
  return true;
}

std::uint32_t SphereFieldChecker::free_lanes_along(const double* const* q, int count, const Eigen::VectorXd& direction,
                                                   double reach) const {
  if (!(reach > 0)) return free_lanes(q, count);
  if (count <= 0 || !certifiable_ || direction.size() != kin_->dof() || !direction.allFinite()) return 0;
  count = std::min(count, LinkPoseLanesD::kLanes);
  thread_local std::vector<float> widen;
  if (!static_widening(direction, reach, widen)) return 0;
  const LaneMotion motion = LaneMotion::start(*this, direction, reach);
  return simd_path() == SimdPath::Avx2 ? free_lanes_avx2(*this, q, count, widen.data(), &motion)
                                       : free_lanes_portable(*this, q, count, widen.data(), &motion);
}

std::vector<SphereFieldChecker::MotionBound> SphereFieldChecker::motion_bounds(const double* const* q, int count,
                                                                               const Eigen::VectorXd& direction,
                                                                               double reach) const {
  std::vector<MotionBound> out;
  if (count <= 0 || !(reach > 0) || !certifiable_ || direction.size() != kin_->dof() || !direction.allFinite())
    return out;
  count = std::min(count, LinkPoseLanesD::kLanes);
  std::vector<float> widen;
  if (!static_widening(direction, reach, widen)) return out;
  const double* in[LinkPoseLanesD::kLanes];
  for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) in[k] = q[k < count ? k : 0];
  LinkPoseLanesF poses;
  kin_->lanes().link_poses(in, poses);
  std::vector<LaneXyz> center(bodies_.size());
  for (std::size_t bi = 0; bi < bodies_.size(); ++bi) {
    const auto& T = poses.pose[std::size_t(bodies_[bi].link)];
    const Eigen::Vector3f c = bodies_[bi].center.cast<float>();
    for (int k = 0; k < LinkPoseLanesD::kLanes; ++k) {
      center[bi].x[k] = T[0][k] * c.x() + T[1][k] * c.y() + T[2][k] * c.z() + T[9][k];
      center[bi].y[k] = T[3][k] * c.x() + T[4][k] * c.y() + T[5][k] * c.z() + T[10][k];
      center[bi].z[k] = T[6][k] * c.x() + T[7][k] * c.y() + T[8][k] * c.z() + T[11][k];
    }
  }
  const LaneMotion motion = LaneMotion::start(*this, direction, reach);
  auto fill = [&](MotionBound& m, float static_bound, auto&& local) {
    for (int k = 0; k < count; ++k) m.metres[std::size_t(k)] = std::min(double(static_bound), double(local(1u << k)));
  };
  for (std::size_t bi = 0; bi < bodies_.size(); ++bi) {
    MotionBound m;
    m.link_a = bodies_[bi].link;
    m.attached = bodies_[bi].attached;
    fill(m, widen[bi], [&](std::uint32_t lane) { return motion.body(*this, bi, poses, center.data(), lane); });
    out.push_back(m);
  }
  for (std::size_t pi = 0; pi < pairs_.size(); ++pi) {
    MotionBound m;
    const Body &a = bodies_[std::size_t(pairs_[pi].a)], &b = bodies_[std::size_t(pairs_[pi].b)];
    m.link_a = a.link;
    m.link_b = b.link;
    m.attached = a.attached || b.attached;
    fill(m, widen[bodies_.size() + pi],
         [&](std::uint32_t lane) { return motion.pair(*this, pi, poses, center.data(), lane); });
    out.push_back(m);
  }
  return out;
}

}  // namespace dmgplace::runtime
