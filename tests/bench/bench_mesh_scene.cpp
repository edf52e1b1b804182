// A mesh robot in a mesh scene (issue 58): the Panda (link meshes) in the MotionBenchMaker kitchen
// (a URDF of meshes), both as `scripts/bake-shared` bakes them. Problems: start and goal drawn
// uniformly in the joint limits (seeded), kept where the exact layer finds them free and the hand
// is inside the kitchen artifact's target volume (the counter top under the cupboard), so the
// arm works near the meshes. Reported as bench-mbm reports the 700: solved, exact-valid, median and
// p95 to the first and to the returned path; and which layer settled the checks: the share of
// checker queries the fast layer settled alone, the share settled without FCL (hull gaps
// included), and the share of 0.5 rad motion checks from the same configurations that needed no
// FCL call. Run after scripts/bake-shared (DMGPLACE_SHARED_ARTIFACTS names another folder):
//   build/release/tests/bench_mesh_scene
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <random>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/runtime/motion/arm_space.hpp"
#include "dmgplace/tools/motion/arm_problem.hpp"
#include "test_support.hpp"

using namespace dmgplace;
namespace fs = std::filesystem;

namespace {

struct Kitchen {
  std::string missing;  // why the benchmark cannot run, if it cannot
  std::unique_ptr<tools::ArmProblem> problem;
  std::vector<Eigen::VectorXd> configs;  // free, hand in the target volume; problem i: 2i -> 2i+1
};

Kitchen& kitchen() {
  static Kitchen k = [] {
    Kitchen out;
    const char* dir = std::getenv("DMGPLACE_SHARED_ARTIFACTS");
    const fs::path artifacts = dir && *dir ? fs::path(dir) : test::source_dir() / "out/shared/artifacts";
    for (const char* f : {"panda.h5", "kitchen.h5"})
      if (!fs::exists(artifacts / f)) out.missing = (artifacts / f).string() + " is missing: run scripts/bake-shared";
    if (!out.missing.empty()) return out;
    const formats::EnvironmentArtifact env = formats::load_environment(artifacts / "kitchen.h5");
    out.problem = std::make_unique<tools::ArmProblem>(
        tools::arm_problem_in_environment(tools::load_arm_robot(artifacts / "panda.h5"), env));
    const runtime::Kinematics& kin = *out.problem->kin;
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    for (int tries = 0; tries < 2000000 && out.configs.size() < 120; ++tries) {
      Eigen::VectorXd q(kin.dof());
      for (int j = 0; j < kin.dof(); ++j) q[j] = kin.lower()[j] + u(rng) * (kin.upper()[j] - kin.lower()[j]);
      if (!env.volume.contains(kin.tip_pose(q).translation())) continue;
      if (out.problem->exact->is_free(q)) out.configs.push_back(q);
    }
    return out;
  }();
  return k;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

// Every problem planned once per iteration (resolution: range(0) / 1000 rad).
void BM_KitchenPlanning(benchmark::State& st) {
  Kitchen& k = kitchen();
  if (!k.missing.empty()) return st.SkipWithError(k.missing.c_str());
  tools::ArmProblem& p = *k.problem;
  const double resolution = double(st.range(0)) / 1000;
  std::vector<double> first, returned;
  long solved = 0, valid = 0, problems = 0;
  const auto& c = p.checker->counters();
  const long fast0 = c.fast, pairs0 = c.exact_pairs, full0 = c.exact_full, gaps0 = c.exact_gaps,
             proven0 = c.proven_collisions;
  for (auto _ : st)
    for (std::size_t i = 0; i + 1 < k.configs.size(); i += 2, ++problems) {
      p.start = k.configs[i];
      p.goal = k.configs[i + 1];
      const tools::PlanOutcome out = tools::plan_ours(p, 10.0, resolution, 1 + i);
      solved += out.solved;
      valid += out.valid;
      if (!out.solved) continue;
      first.push_back(1e3 * out.first_path_seconds);
      returned.push_back(1e3 * out.seconds);
    }
  const double queries = double(c.fast - fast0), fcl = double(c.exact_pairs - pairs0 + c.exact_full - full0);
  st.counters["problems"] = double(problems);
  st.counters["solved"] = double(solved);
  st.counters["valid"] = double(valid);
  st.counters["first_median_ms"] = percentile(first, 0.5);
  st.counters["first_p95_ms"] = percentile(first, 0.95);
  st.counters["returned_median_ms"] = percentile(returned, 0.5);
  st.counters["returned_p95_ms"] = percentile(returned, 0.95);
  st.counters["fast_alone_share"] = queries > 0 ? 1 - (fcl + double(c.exact_gaps - gaps0)) / queries : 0;
  st.counters["no_fcl_share"] = queries > 0 ? 1 - fcl / queries : 0;
  st.counters["queries"] = queries;
  st.counters["proven_collisions"] = double(c.proven_collisions - proven0);
  st.counters["exact_pairs"] = double(c.exact_pairs - pairs0);
  st.counters["exact_full"] = double(c.exact_full - full0);
}
BENCHMARK(BM_KitchenPlanning)->Arg(10)->Arg(31)->Iterations(1)->Unit(benchmark::kMillisecond);

// 0.5 rad motions from each configuration in a seeded random direction, checked as planners check
// them (resolution 0.01 rad): the share that needed no FCL call, and that the fast layer settled
// alone (no hull gap either).
void BM_KitchenMotionChecks(benchmark::State& st) {
  Kitchen& k = kitchen();
  if (!k.missing.empty()) return st.SkipWithError(k.missing.c_str());
  tools::ArmProblem& p = *k.problem;
  const runtime::Kinematics& kin = *p.kin;
  auto si = runtime::make_arm_space(kin, *p.checker, 0.01);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 1);
  std::vector<std::pair<ompl::base::State*, ompl::base::State*>> motions;
  for (const auto& q : k.configs) {
    Eigen::VectorXd d(q.size());
    for (Eigen::Index j = 0; j < d.size(); ++j) d[j] = g(rng);
    const Eigen::VectorXd b = (q + 0.5 * d.normalized()).cwiseMax(kin.lower()).cwiseMin(kin.upper());
    auto* s1 = si->allocState();
    auto* s2 = si->allocState();
    si->getStateSpace()->copyFromReals(s1, std::vector<double>(q.data(), q.data() + q.size()));
    si->getStateSpace()->copyFromReals(s2, std::vector<double>(b.data(), b.data() + b.size()));
    motions.emplace_back(s1, s2);
  }
  const auto& c = p.checker->counters();
  long checked = 0, no_fcl = 0, fast_alone = 0, valid = 0;
  for (auto _ : st)
    for (const auto& [s1, s2] : motions) {
      const long fcl0 = c.exact_pairs + c.exact_full, gaps0 = c.exact_gaps;
      valid += si->checkMotion(s1, s2);
      const bool without_fcl = c.exact_pairs + c.exact_full == fcl0;
      no_fcl += without_fcl;
      fast_alone += without_fcl && c.exact_gaps == gaps0;
      ++checked;
    }
  for (auto& [s1, s2] : motions) {
    si->freeState(s1);
    si->freeState(s2);
  }
  st.counters["motions"] = double(checked);
  st.counters["valid_share"] = double(valid) / double(std::max(1L, checked));
  st.counters["no_fcl_share"] = double(no_fcl) / double(std::max(1L, checked));
  st.counters["fast_alone_share"] = double(fast_alone) / double(std::max(1L, checked));
}
BENCHMARK(BM_KitchenMotionChecks)->Iterations(3)->Unit(benchmark::kMillisecond);

}  // namespace
BENCHMARK_MAIN();
