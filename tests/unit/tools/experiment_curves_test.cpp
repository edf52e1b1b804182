// What `dmgplace plot` draws and `experiment` summarises, checked against direct computation on
// synthetic runs; spec files with mistakes are rejected naming the file and the element.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/experiment/experiment_plots.hpp"
#include "dmgplace/tools/experiment/experiment_results.hpp"
#include "dmgplace/tools/experiment/experiment_spec.hpp"
#include "test_support.hpp"

using namespace dmgplace;
using namespace dmgplace::tools;

namespace {
// Runs whose objective improves at random times, some never solved.
std::vector<RunRecord> random_runs(std::mt19937_64& rng) {
  std::vector<RunRecord> runs;
  std::uniform_real_distribution<double> u(0, 1);
  for (const char* variant : {"full", "no-regrasp"})
    for (int seed = 1; seed <= 9; ++seed) {
      RunRecord r;
      r.problem = "p";
      r.variant = variant;
      r.seed = seed;
      r.time_limit = 10;
      double t = 0, v = 0;
      const int n = int(u(rng) * 5);  // 0 .. 4 improvements; 0: never solved
      for (int k = 0; k < n; ++k) {
        t += u(rng) * 3;
        v += u(rng);
        if (t < 10) r.improvements.emplace_back(t, v);
      }
      r.solved = !r.improvements.empty();
      runs.push_back(r);
    }
  return runs;
}
}  // namespace

TEST(ExperimentCurves, MeanStandardErrorAndSolvedFractionMatchDirectComputation) {
  std::mt19937_64 rng(11);
  const auto runs = random_runs(rng);
  const auto curves = experiment_curves(runs, 50);
  ASSERT_EQ(curves.size(), 2u);
  for (const auto& c : curves) {
    EXPECT_EQ(c.runs, 9);
    ASSERT_EQ(c.t.size(), 51u);
    EXPECT_DOUBLE_EQ(c.t.back(), 10);
    for (std::size_t k = 0; k < c.t.size(); ++k) {
      std::vector<double> v;
      for (const auto& r : runs)
        if (r.variant == c.variant && !r.improvements.empty() && r.improvements.front().first <= c.t[k])
          v.push_back(r.best_at(c.t[k]));
      ASSERT_EQ(c.with_solution[k], int(v.size())) << c.variant << " t=" << c.t[k];
      EXPECT_DOUBLE_EQ(c.solved_fraction[k], double(v.size()) / 9);
      if (v.empty()) {
        EXPECT_TRUE(std::isnan(c.mean[k]));
        continue;
      }
      double mean = 0;
      for (double x : v) mean += x;
      mean /= double(v.size());
      double ss = 0;
      for (double x : v) ss += (x - mean) * (x - mean);
      const double se = v.size() > 1 ? std::sqrt(ss / double(v.size() - 1) / double(v.size())) : 0.0;
      EXPECT_NEAR(c.mean[k], mean, 1e-9);
      EXPECT_NEAR(c.stderr_[k], se, 1e-9);
    }
    // Solutions are never lost: the fraction never drops over time.
    for (std::size_t k = 1; k < c.t.size(); ++k) EXPECT_GE(c.solved_fraction[k], c.solved_fraction[k - 1]);
  }
}

TEST(ExperimentCurves, BestAtIsTheLastImprovementSoFar) {
  RunRecord r;
  r.improvements = {{0.5, 1.0}, {2.0, 1.5}, {7.0, 2.5}};
  EXPECT_TRUE(std::isnan(r.best_at(0.4)));
  EXPECT_DOUBLE_EQ(r.best_at(0.5), 1.0);
  EXPECT_DOUBLE_EQ(r.best_at(6.9), 1.5);
  EXPECT_DOUBLE_EQ(r.best_at(100), 2.5);
  EXPECT_DOUBLE_EQ(r.first_time(), 0.5);
}

TEST(ExperimentSpecFile, MistakesNameTheFileAndTheElement) {
  test::TempDir dir;
  test::write_text(dir / "q.yaml", "robot: r.h5\n");
  auto spec_error = [&](const std::string& text) {
    test::write_text(dir / "s.yaml", text);
    return test::error_of([&] { read_experiment_spec(dir / "s.yaml"); });
  };
  const std::string file = (dir / "s.yaml").string();
  auto e = spec_error("name: x\nproblems:\n  - {name: a, query: q.yaml, variants: [full, sideways]}\n");
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find("unknown variant 'sideways'"), std::string::npos) << e;
  e = spec_error("name: x\nproblems: []\n");
  EXPECT_NE(e.find("problems"), std::string::npos) << e;
  e = spec_error("runs: 0\nproblems:\n  - {name: a, query: q.yaml}\n");
  EXPECT_NE(e.find("must be in [1, 100000]"), std::string::npos) << e;
  e = spec_error("time_limit: 1e12\nproblems:\n  - {name: a, query: q.yaml}\n");
  EXPECT_NE(e.find("time_limit: must be a number of seconds in [0, 1e6]"), std::string::npos) << e;
  e = spec_error("problem:\n  - {name: a, query: q.yaml}\n");  // a typo is not ignored
  EXPECT_NE(e.find("problem (line 1): unknown key"), std::string::npos) << e;
  e = spec_error("problems:\n  - {name: a, query: q.yaml, variant: full}\n");
  EXPECT_NE(e.find("problems[0].variant"), std::string::npos) << e;
  e = spec_error("problems:\n  - {name: a, query: q.yaml}\n  - {name: a, query: q.yaml}\n");
  EXPECT_NE(e.find("appears twice"), std::string::npos) << e;
  e = spec_error("problems:\n  - {name: 'a b', query: q.yaml}\n");
  EXPECT_NE(e.find("non-empty word"), std::string::npos) << e;
  e = spec_error("problems: [\n");
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find("line"), std::string::npos) << e;
  // A good one: defaults and paths relative to the spec.
  test::write_text(dir / "s.yaml", "problems:\n  - {name: a, query: q.yaml}\n");
  const auto s = read_experiment_spec(dir / "s.yaml");
  ASSERT_EQ(s.problems.size(), 1u);
  EXPECT_EQ(s.problems[0].query, dir / "q.yaml");
  EXPECT_EQ(s.problems[0].variants.size(), 1u);
}
