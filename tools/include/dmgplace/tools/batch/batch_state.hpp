#pragma once
// A batch's state on disk, safe against kill -9 and shared by shards on one filesystem:
//   OUT/batch.json           the plan (tasks, identities, outputs), rewritten by every run
//   OUT/state/<id>.json      a finished task's record, written last, after its output
//   OUT/state/<id>.lock      a claim: created exclusively by the process running the task
// A task is done when its record says so, names its identity and its output is on disk and sound.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/tools/batch/batch_plan.hpp"

namespace dmgplace::tools {

struct TaskRecord {
  std::string id, name, kind;
  bool ok = false;
  int exit_code = 0;
  double seconds = 0;
  std::string error;        // the failing command's error line (file, element, reason)
  std::string stderr_tail;  // its last lines
  std::string finished_utc;
};

void write_plan(const BatchPlan& plan);
BatchPlan read_plan(const std::filesystem::path& out);  // throws naming OUT/batch.json
void write_record(const std::filesystem::path& out, const TaskRecord& r);
std::optional<TaskRecord> read_record(const std::filesystem::path& out, const std::string& id);
// The record says done and the output is there (an artifact that validates, a run's result.json).
bool task_done(const std::filesystem::path& out, const BatchTask& t);

// Removes claims left by killed processes of this host (a run killed between a task's record and
// the release of its claim), so a finished batch leaves no litter.
void remove_stale_claims(const std::filesystem::path& out);

// An exclusive claim on a task (OUT/state/<id>.lock); a claim whose process is gone (same host) is
// taken over. Released by the destructor.
class TaskClaim {
 public:
  static std::optional<TaskClaim> try_claim(const std::filesystem::path& out, const std::string& id);
  TaskClaim(TaskClaim&& o) noexcept : path_(std::move(o.path_)) { o.path_.clear(); }
  TaskClaim& operator=(TaskClaim&&) = delete;
  ~TaskClaim();

 private:
  explicit TaskClaim(std::filesystem::path p) : path_(std::move(p)) {}
  std::filesystem::path path_;
};

}  // namespace dmgplace::tools
