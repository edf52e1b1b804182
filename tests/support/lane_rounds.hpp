#pragma once
// Random configurations and lane checks of 8 of them on every SIMD path: the lane kinematics and
// sphere check tests share these.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <random>
#include <vector>

#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/runtime/robot/kinematics_lanes.hpp"
#include "dmgplace/runtime/system/simd_dispatch.hpp"

namespace dmgplace::test {

// A configuration drawn uniformly within the chain's limits.
inline Eigen::VectorXd random_q(const runtime::Kinematics& k, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::VectorXd q(k.dof());
  for (int i = 0; i < k.dof(); ++i) q[i] = k.lower()[i] + u(rng) * (k.upper()[i] - k.lower()[i]);
  return q;
}

// `rounds` lane checks of 8 random configurations on each SIMD path (the portable one, then AVX2 where
// the CPU has it): widen(round, q) may change each configuration, then check(qs, ptr) runs.
template <class Widen, class Check>
void lane_rounds_on_every_path(const runtime::Kinematics& kin, std::uint64_t seed, int rounds, Widen widen,
                               Check check) {
  using runtime::SimdPath;
  std::mt19937_64 rng(seed);
  const runtime::ScopedSimdPath restore_simd;  // forced paths end with the test
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Avx2}) {
    runtime::force_simd_path(path);
    for (int round = 0; round < rounds; ++round) {
      std::vector<Eigen::VectorXd> qs;
      const double* ptr[runtime::LinkPoseLanesD::kLanes];
      for (int k = 0; k < runtime::LinkPoseLanesD::kLanes; ++k) {
        qs.push_back(random_q(kin, rng));
        widen(round, qs.back());
      }
      for (int k = 0; k < runtime::LinkPoseLanesD::kLanes; ++k) ptr[k] = qs[std::size_t(k)].data();
      check(qs, ptr);
      if (::testing::Test::HasFatalFailure()) break;  // an ASSERT in check returns from check only
    }
  }
}

// lane_rounds_on_every_path with the configurations as drawn.
template <class Check>
void lane_rounds_on_every_path(const runtime::Kinematics& kin, std::uint64_t seed, int rounds, Check check) {
  lane_rounds_on_every_path(
      kin, seed, rounds, [](int, Eigen::VectorXd&) {}, check);
}

}  // namespace dmgplace::test
