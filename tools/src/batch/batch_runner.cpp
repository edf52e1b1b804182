#include "dmgplace/tools/batch/batch_runner.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>
#include <thread>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/batch/batch_state.hpp"
#include "dmgplace/tools/system/process.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;
namespace {
using Clock = std::chrono::steady_clock;

std::string tail(const std::string& s, std::size_t n) { return s.size() > n ? s.substr(s.size() - n) : s; }

// The child's own error line ("error: FILE: ELEMENT: REASON"), or its last line.
std::string error_line(const std::string& err, int code) {
  const auto at = err.rfind("error: ");
  if (at != std::string::npos) return err.substr(at + 7, err.find('\n', at) - at - 7);
  return "exit status " + std::to_string(code);
}

class Runner {
 public:
  Runner(const BatchPlan& plan, const BatchOptions& o, std::ostream& out, std::ostream& progress)
      : plan_(plan), o_(o), out_(out), progress_(progress), tty_(::isatty(STDERR_FILENO) == 1) {
    for (std::size_t i = 0; i < plan.tasks.size(); ++i) index_[plan.tasks[i].id] = i;
  }

  BatchTotals run() {
    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < plan_.tasks.size(); ++i) {
      const auto& t = plan_.tasks[i];
      const bool phase = o_.phase == "all" || (o_.phase == "bakes") == (t.kind != "query");
      if (phase && in_shard(plan_, i, o_.shard_index, o_.shard_count)) mine.push_back(i);
    }
    totals_.planned = int(mine.size());
    std::vector<std::size_t> todo;
    for (std::size_t i : mine) {
      if (task_done(plan_.out, plan_.tasks[i])) ++totals_.done_before, done_.insert(plan_.tasks[i].id);
      else todo.push_back(i);
    }
    progress_ << plan_.name << ": " << totals_.planned << " tasks in this shard (" << totals_.done_before
              << " already done), " << o_.jobs << " at a time\n";
    if (o_.dry_run) {
      for (std::size_t i : todo)
        out_ << "would run: " << plan_.tasks[i].name << "  (" << plan_.tasks[i].id.substr(0, 12) << ")\n";
      return totals_;
    }
    t0_ = Clock::now();
    left_ = int(todo.size());
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
      for (std::size_t k; (k = next++) < todo.size();) ensure(todo[k]);
    };
    std::vector<std::thread> pool;
    for (int j = 0; j < std::max(1, o_.jobs); ++j) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
    if (tty_) progress_ << "\n";
    return totals_;
  }

 private:
  // Runs task i unless it is done; waits while another process or thread holds it. True when done.
  bool ensure(std::size_t i) {
    const BatchTask& t = plan_.tasks[i];
    for (;;) {
      if (known_done(t.id)) return true;  // a query's bakes are checked once, not once per query
      if (task_done(plan_.out, t)) return remember_done(t.id);
      if (const auto r = read_record(plan_.out, t.id); r && !r->ok && attempted(t.id)) return false;  // failed this run
      if (auto claim = TaskClaim::try_claim(plan_.out, t.id)) {
        if (task_done(plan_.out, t)) return remember_done(t.id);  // finished while we were claiming
        return execute(t) && remember_done(t.id);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(200));  // held by someone running it
    }
  }

  // Done tasks stay done for this run: validating an artifact reads it whole.
  bool known_done(const std::string& id) {
    std::lock_guard<std::mutex> lock(mutex_);
    return done_.count(id) > 0;
  }
  bool remember_done(const std::string& id) {
    std::lock_guard<std::mutex> lock(mutex_);
    done_.insert(id);
    return true;
  }

  bool attempted(const std::string& id) {
    std::lock_guard<std::mutex> lock(mutex_);
    return attempted_.count(id) > 0;
  }

  bool execute(const BatchTask& t) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      attempted_.insert(t.id);
    }
    const auto start = Clock::now();
    TaskRecord rec;
    rec.id = t.id, rec.name = t.name, rec.kind = t.kind;
    for (const auto& dep : t.deps) {  // a query's bakes: ours, another shard's, or nobody's yet
      if (!ensure(index_.at(dep))) {
        rec.error = "needs " + plan_.tasks[index_.at(dep)].name + ", which failed";
        return finish(t, rec, start);
      }
    }
    try {
      if (t.kind == "query") {
        fs::create_directories(t.output);
        formats::write_file_atomically(t.output / "query.yaml", t.query_yaml);
      } else {
        fs::create_directories(t.output.parent_path());
      }
      std::vector<std::string> argv{o_.cli.string()};
      argv.insert(argv.end(), t.args.begin(), t.args.end());
      ProcessOptions po;
      po.stderr_to = StderrTo::capture;
      const ProcessResult r = run_process(argv, po);
      rec.exit_code = r.signal ? 128 + r.signal : r.exit_code;
      // place exits 3 when it finds no placement: a result, not a failure.
      rec.ok = r.exit_code == 0 || (t.kind == "query" && r.exit_code == 3);
      if (!rec.ok)
        rec.error = r.signal ? "killed by signal " + std::to_string(r.signal) : error_line(r.error_output, r.exit_code);
      rec.stderr_tail = tail(r.error_output, 2000);
      if (rec.ok && t.kind != "query" && !fs::exists(t.output)) rec.ok = false, rec.error = "no output written";
      if (rec.ok && t.kind != "query" && o_.deep) validate_deeply(t, rec);
    } catch (const std::exception& e) {
      rec.ok = false;
      rec.error = e.what();
    }
    return finish(t, rec, start);
  }

  // A bake's output held against its own geometry (`validate --deep`) before any query plans with it.
  void validate_deeply(const BatchTask& t, TaskRecord& rec) {
    ProcessOptions po;
    po.stderr_to = StderrTo::merge;
    const ProcessResult r = run_process({o_.cli.string(), "validate", "--deep", "--quiet", t.output.string()}, po);
    if (r.exit_code == 0) return;
    rec.ok = false;
    // --quiet prints problems only, one a line: the first names the dataset and the worst sample.
    const std::string first = r.output.substr(0, r.output.find('\n'));
    rec.error = "validate --deep: " + (first.empty() ? "exit status " + std::to_string(r.exit_code) : first);
    rec.stderr_tail += tail(r.output, 2000);
  }

  bool finish(const BatchTask& t, TaskRecord& rec, Clock::time_point start) {
    rec.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    write_record(plan_.out, rec);  // last: the output is already on disk
    std::lock_guard<std::mutex> lock(mutex_);
    (rec.ok ? totals_.ran : totals_.failed)++;
    --left_;
    const int finished = totals_.ran + totals_.failed;
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0_).count();
    const double eta = finished ? elapsed / finished * left_ : 0;
    if (o_.json)
      out_ << nlohmann::json{{"id", t.id},
                             {"name", t.name},
                             {"ok", rec.ok},
                             {"seconds", rec.seconds},
                             {"error", rec.error}}
                  .dump()
           << std::endl;
    if (tty_) {
      progress_ << "\r[" << finished << "/" << totals_.planned - totals_.done_before << "] " << totals_.failed
                << " failed, ETA " << int(eta) << " s   " << std::flush;
      if (!rec.ok) progress_ << "\nFAILED " << t.name << ": " << rec.error << "\n";
    } else {
      progress_ << (rec.ok ? "ok     " : "FAILED ") << t.name << " (" << rec.seconds << " s)"
                << (rec.ok ? "" : ": " + rec.error) << "\n";
    }
    return rec.ok;
  }

  const BatchPlan& plan_;
  const BatchOptions& o_;
  std::ostream& out_;
  std::ostream& progress_;
  const bool tty_;
  std::map<std::string, std::size_t> index_;
  std::set<std::string> attempted_, done_;
  std::mutex mutex_;
  BatchTotals totals_;
  int left_ = 0;
  Clock::time_point t0_;
};

}  // namespace

BatchTotals run_batch(const BatchPlan& plan, const BatchOptions& o, std::ostream& out, std::ostream& progress) {
  if (o.jobs < 1 || o.shard_count < 1 || o.shard_index < 1 || o.shard_index > o.shard_count)
    throw Error("batch", "options", "jobs >= 1 and a shard I/N with 1 <= I <= N");
  if (o.phase != "all" && o.phase != "bakes" && o.phase != "queries")
    throw Error("batch", "--phase", "all, bakes or queries");
  write_plan(plan);
  remove_stale_claims(plan.out);
  return Runner(plan, o, out, progress).run();
}

}  // namespace dmgplace::tools
