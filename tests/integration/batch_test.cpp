// `dmgplace batch` (issue 17): a manifest's tasks run once, resume after kill -9 without losing or
// repeating work, shard into a partition of one run, re-run exactly what a changed input touches,
// and record failures as data. The manifest is small (dmgarm, the eraser, a table corner) and its
// queries stop after a number of rounds, so every run gives the same objectives.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <span>
#include <thread>
#include <set>

#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "dmgplace/tools/batch/batch_state.hpp"
#include "dmgplace/tools/geometry/procedural_meshes.hpp"
#include "run_cli.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace dmgplace;
using ::testing::HasSubstr;

namespace {

struct Batch {
  test::TempDir dir;
  fs::path manifest = dir / "m.yaml";
  explicit Batch(bool with_broken_object = false) {
    test::run_cli({"make-objects", "--out", dir.path()});
    const fs::path data = test::source_dir() / "datasets";
    std::string m = "name: t\nrobots:\n  arm: {urdf: " + (data / "robots/dmgarm/dmgarm.urdf").string() +
                    ", srdf: " + (data / "robots/dmgarm/dmgarm.srdf").string() +
                    ", arm: \"dmgarm_link0:dmgarm_tcp\"}\n" + "objects:\n  eraser: {mesh: eraser.stl}\n";
    if (with_broken_object) {
      test::write_text(dir / "broken.stl", "solid nothing\nendsolid\n");
      m += "  broken: {mesh: broken.stl}\n";
    }
    m += "environments:\n  table: {scene: " + (data / "scenes/table.yaml").string() +
         ", volume: [0.3, -0.3, 0.4, 0.8, 0.3, 0.7], flags: [--resolution, \"0.02\", --margin, \"0.9\", "
         "--sdf-resolution, \"0.04\","
         " --band, \"0.25\"]}\n"
         "queries:\n  - name: q\n    robot: arm\n    objects: [eraser" +
         std::string(with_broken_object ? ", broken" : "") +
         "]\n    environments: [table]\n    initial_grasps: {top: [0, 0, 0.0175, 1, 0, 0, 0]}\n"
         "    start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]\n    variants: [full, no-regrasp]\n    seeds: 2\n"
         "    time_limit: 60\n    iterations: 40\n";
    test::write_text(manifest, m);
  }
  tools::ProcessResult run(const fs::path& out, std::vector<test::Arg> extra = {}) const {
    std::vector<test::Arg> args{"batch", manifest, "--out", out};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args);
  }
};

// "N ran, M failed, K were done" from the runner's last line.
std::array<int, 3> counts(const std::string& output) {
  std::array<int, 3> c{-1, -1, -1};
  const auto at = output.rfind(" ran, ");
  if (at == std::string::npos) return c;
  const auto line = output.rfind('\n', at) == std::string::npos ? 0 : output.rfind('\n', at) + 1;
  std::sscanf(output.c_str() + line, "%d ran, %d failed, %d were done", &c[0], &c[1], &c[2]);
  return c;
}

// Every deterministic column of a collected dataset (all but the clock's), by its digest.
std::map<std::string, std::string> dataset_digest(const fs::path& out) {
  const fs::path d = out / "dataset.h5";
  const auto r = test::run_cli({"batch-collect", out, "--out", d});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  formats::H5Reader h(d);
  const std::set<std::string> timed{"runs/first_solution_time", "runs/seconds", "runs/solution_time", "trace/time"};
  std::map<std::string, std::string> m;
  for (const auto& c : h.dataset_names())
    if (!timed.count(c)) m[c] = h.attribute(c, "sha256").value_or("?");
  for (const char* c : {"runs/task_id", "runs/objective", "runs/pose_x", "path/q0", "actions/type", "trace/objective"})
    EXPECT_TRUE(m.count(c)) << c << " missing from " << d;
  return m;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(test::read_text(p)); }

// The rows of run i in `table`, from offsets/.
std::pair<std::size_t, std::size_t> rows_of(const formats::H5Reader& h, const std::string& table, std::size_t i) {
  const auto off = h.read_i64("offsets/" + table, {-1}).data;
  return {std::size_t(off.at(i)), std::size_t(off.at(i + 1))};
}

// Run i's arm path (path/q0 ... of its rows) equals result.json's best.path, value for value.
void expect_path_equals(const formats::H5Reader& h, std::size_t i, const nlohmann::json& best) {
  const auto [begin, end] = rows_of(h, "path", i);
  ASSERT_EQ(end - begin, best.at("path").size()) << "run " << i;
  EXPECT_EQ(h.read_i64("runs/path_waypoints", {-1}).data.at(i), std::int64_t(end - begin));
  for (std::size_t j = 0; j < best.at("path").at(0).size(); ++j) {
    const auto q = h.read_f64("path/q" + std::to_string(j), {-1}).data;
    for (std::size_t k = begin; k < end; ++k) EXPECT_EQ(q[k], best["path"][k - begin][j].get<double>()) << "run " << i;
  }
  for (std::size_t k = begin; k < end; ++k) EXPECT_EQ(h.read_i64("path/run", {-1}).data[k], std::int64_t(i));
}

// Run i's in-hand actions equal result.json's best.in_hand, and its trace its improvements.
void expect_actions_and_trace_equal(const formats::H5Reader& h, std::size_t i, const nlohmann::json& result) {
  const auto& in_hand = result.at("best").at("in_hand");
  const auto [begin, end] = rows_of(h, "actions", i);
  ASSERT_EQ(end - begin, in_hand.size()) << "run " << i;
  const auto type = h.read_utf8_strings("actions/type");
  const auto from = h.read_i64("actions/from_state", {-1}).data, to = h.read_i64("actions/to_state", {-1}).data;
  const auto distance = h.read_f64("actions/distance", {-1}).data, angle = h.read_f64("actions/angle", {-1}).data;
  for (std::size_t k = begin; k < end; ++k) {
    const auto& a = in_hand[k - begin];
    EXPECT_EQ(type[k], a.at("type").get<std::string>());
    EXPECT_EQ(from[k], a.at("from_state").get<std::int64_t>());
    EXPECT_EQ(to[k], a.at("to_state").get<std::int64_t>());
    if (type[k] == "push") EXPECT_EQ(distance[k], a.at("distance").get<double>());
    else EXPECT_EQ(angle[k], a.at("angle").get<double>());
  }
  const auto [first, last] = rows_of(h, "trace", i);
  ASSERT_EQ(last - first, result.at("improvements").size());
  const auto objective = h.read_f64("trace/objective", {-1}).data;
  for (std::size_t k = first; k < last; ++k)
    EXPECT_EQ(objective[k], result["improvements"][k - first].at("objective").get<double>());
}

// A copy of a dataset with `change` applied to its integer columns and `version` as its schema version.
void copy_dataset(const fs::path& from, const fs::path& to, int version,
                  const std::function<void(const std::string&, std::vector<std::int64_t>&)>& change) {
  formats::H5Reader r(from);
  formats::ArtifactHeader header = r.header();
  header.schema_version = version;
  formats::H5Writer w(to, header);
  for (const auto& name : r.dataset_names()) {
    const auto n = r.shape(name).at(0);
    try {
      w.write_utf8_strings(name, r.read_utf8_strings(name));
      continue;
    } catch (const Error&) {
    }
    try {
      w.write(name, std::span<const double>(r.read_f64(name, {-1}).data), {n});
      continue;
    } catch (const Error&) {
    }
    try {
      auto v = r.read_i64(name, {-1}).data;
      change(name, v);
      w.write(name, std::span<const std::int64_t>(v), {n});
      continue;
    } catch (const Error&) {
    }
    w.write(name, std::span<const std::uint8_t>(r.read_u8(name, {-1}).data), {n});
  }
  w.commit();
}

std::vector<std::string> litter(const fs::path& out) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    const std::string n = e.path().filename().string();
    if (n.find(".tmp") != std::string::npos || n.ends_with(".lock")) found.push_back(e.path().string());
  }
  return found;
}

// A finished batch: a further run runs nothing, its dataset equals `reference`, nothing is left over.
void expect_complete(const Batch& b, const fs::path& out, const std::map<std::string, std::string>& reference) {
  EXPECT_EQ(counts(b.run(out).output)[0], 0);
  EXPECT_EQ(dataset_digest(out), reference);
  EXPECT_THAT(litter(out), ::testing::IsEmpty());
}

}  // namespace

TEST(Batch, RunsOnceResumesShardsAndCollects) {
  Batch b;
  const fs::path one = b.dir / "one";
  auto r = b.run(one, {"--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{7, 0, 0}));  // 3 bakes, 4 queries
  r = b.run(one);
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{0, 0, 7})) << "a second run runs nothing";
  const auto status = test::run_cli({"batch-status", one, "--json"});
  EXPECT_THAT(status.output, HasSubstr("\"done\": 7"));
  const auto reference = dataset_digest(one);
  EXPECT_EQ(test::run_cli({"validate", one / "dataset.h5"}).exit_code, 0);

  // Three shards, one after another, give exactly one run's tasks, each run once.
  const fs::path sharded = b.dir / "sharded";
  int ran = 0;
  for (const char* s : {"1/3", "2/3", "3/3"}) {
    r = b.run(sharded, {"--shard", s});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    ran += counts(r.output)[0];
  }
  EXPECT_EQ(ran, 7);
  expect_complete(b, sharded, reference);
}

TEST(Batch, KilledAtRandomMomentsLosesAndRepeatsNothing) {
  Batch b;
  const fs::path reference_out = b.dir / "reference";
  ASSERT_EQ(b.run(reference_out).exit_code, 0);
  const auto reference = dataset_digest(reference_out);
  const fs::path out = b.dir / "killed";
  std::mt19937 rng(17);
  for (int k = 0; k < 10; ++k) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int devnull = ::open("/dev/null", O_WRONLY);
      ::dup2(devnull, 1), ::dup2(devnull, 2);
      const std::string cli = test::cli_path(), m = b.manifest.string(), o = out.string();
      ::execl(cli.c_str(), cli.c_str(), "batch", m.c_str(), "--out", o.c_str(), "--jobs", "2", (char*)nullptr);
      ::_exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(50, 1500)(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
  }
  const auto r = b.run(out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_complete(b, out, reference);
}

TEST(Batch, AChangedMeshReRunsOnlyWhatDependsOnIt) {
  Batch b;
  const fs::path out = b.dir / "out";
  ASSERT_EQ(b.run(out).exit_code, 0);
  tools::write_stl_binary(tools::make_box_mesh({0.12, 0.05, 0.035}),
                          b.dir / "eraser.stl");  // a slightly shorter eraser
  const auto r = b.run(out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{5, 0, 2}))
      << r.output;  // the object and its 4 queries; robot, table kept
}

TEST(Batch, ABrokenInputFailsOnlyItsOwnTasks) {
  Batch b(true);
  const fs::path out = b.dir / "out";
  const auto r = b.run(out, {"--json"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(counts(r.output), (std::array<int, 3>{7, 5, 0})) << r.output;  // broken bake + its 4 queries
  const auto s = test::run_cli({"batch-status", out});
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_THAT(s.output, HasSubstr("failed  object broken: "));
  EXPECT_THAT(s.output, HasSubstr("broken.stl"));
  EXPECT_THAT(s.output, HasSubstr("needs object broken, which failed"));
  EXPECT_THAT(r.output, HasSubstr("\"ok\":false"));  // --json: one object per finished task
}

TEST(Batch, CollectedTablesEqualEachRunsResult) {
  Batch b;
  const fs::path out = b.dir / "out";
  ASSERT_EQ(b.run(out, {"--jobs", "2"}).exit_code, 0);
  const fs::path d = out / "dataset.h5", csv = out / "runs.csv";
  const auto r = test::run_cli({"batch-collect", out, "--out", d, "--csv", csv});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(test::run_cli({"validate", d}).exit_code, 0);
  formats::H5Reader h(d);
  const auto ids = h.read_utf8_strings("runs/task_id");
  ASSERT_EQ(ids.size(), 4u);
  std::map<std::string, fs::path> folder;
  for (const auto& t : tools::read_plan(out).tasks) folder[t.id] = t.output;
  int with_actions = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto result = read_json(folder.at(ids[i]) / "result.json");
    ASSERT_TRUE(result.at("solved").get<bool>()) << ids[i];
    expect_path_equals(h, i, result.at("best"));
    expect_actions_and_trace_equal(h, i, result);
    with_actions += !result["best"]["in_hand"].empty();
    EXPECT_EQ(h.read_i64("runs/iterations", {-1}).data[i], result.at("counters").at("iterations").get<std::int64_t>());
  }
  EXPECT_GT(with_actions, 0) << "no run has in-hand actions: the comparison above proves little";
  // The CSV: a header, then one line per run in the dataset's order.
  std::istringstream lines(test::read_text(csv));
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_THAT(rows[0], ::testing::StartsWith("task_id,robot,object,environment,grasp,variant,seed,"));
  for (std::size_t i = 0; i < ids.size(); ++i)
    EXPECT_THAT(rows[i + 1], ::testing::StartsWith(ids[i] + ",arm,eraser,table,top,"));
}

TEST(Batch, ValidateRefusesADatasetWhoseTablesDisagree) {
  Batch b;
  const fs::path out = b.dir / "out";
  ASSERT_EQ(b.run(out).exit_code, 0);
  ASSERT_EQ(test::run_cli({"batch-collect", out, "--out", out / "d.h5"}).exit_code, 0);
  const auto keep = [](const std::string&, std::vector<std::int64_t>&) {};
  copy_dataset(out / "d.h5", out / "same.h5", 2, keep);
  EXPECT_EQ(test::run_cli({"validate", out / "same.h5"}).exit_code, 0) << "the copy itself is sound";
  copy_dataset(out / "d.h5", out / "moved.h5", 2, [](const std::string& name, std::vector<std::int64_t>& v) {
    if (name == "path/run") v.front() = 1;  // the first waypoint claims to be the second run's
  });
  auto r = test::run_cli({"validate", out / "moved.h5"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("moved.h5: path/run: row 0 is not run 0"));
  copy_dataset(out / "d.h5", out / "short.h5", 2, [](const std::string& name, std::vector<std::int64_t>& v) {
    if (name == "runs/in_hand_actions") ++v.back();
  });
  r = test::run_cli({"validate", out / "short.h5"});
  EXPECT_THAT(r.output, HasSubstr("short.h5: offsets/actions: disagrees at run 3"));
  copy_dataset(out / "d.h5", out / "old.h5", 1, keep);
  r = test::run_cli({"validate", out / "old.h5"});
  EXPECT_THAT(r.output, HasSubstr("old.h5: schema_version: is 1, this build reads version 2"));
}

TEST(Batch, CollectNamesTheFileAndFieldOfABadResult) {
  Batch b;
  const fs::path out = b.dir / "out";
  ASSERT_EQ(b.run(out).exit_code, 0);
  fs::path result;
  for (const auto& t : tools::read_plan(out).tasks)
    if (t.kind == "query") result = t.output / "result.json";
  auto j = read_json(result);
  j["best"]["in_hand"] = {{{"type", "twist"}}};
  test::write_text(result, j.dump());
  auto r = test::run_cli({"batch-collect", out, "--out", out / "d.h5"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr(result.string() + ": best/in_hand/0/type: is 'twist', expected push or rotate"));
  j["best"].erase("path");
  test::write_text(result, j.dump());
  EXPECT_THAT(test::run_cli({"batch-collect", out, "--csv", out / "r.csv"}).output,
              HasSubstr(result.string() + ": best/path: missing"));
  test::write_text(result, "{\"solved\": tr");
  EXPECT_THAT(test::run_cli({"batch-collect", out, "--out", out / "d.h5"}).output,
              HasSubstr(result.string() + ": not valid JSON"));
  r = test::run_cli({"batch-collect", out});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("give --out DATASET.h5, --csv FILE.csv or both"));
  EXPECT_FALSE(fs::exists(out / "d.h5") || fs::exists(out / "r.csv")) << "nothing is written from a bad batch";
}
