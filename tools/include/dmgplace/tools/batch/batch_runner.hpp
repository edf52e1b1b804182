#pragma once
// Runs a batch plan: each task is `dmgplace <args>` in a child process (a crash or an exhausted
// memory limit fails that task only), bakes before the queries that need them, `jobs` at a time.
// Finished tasks are skipped (their identity, record and output agree), failures are recorded and
// the rest go on. Shards claim tasks (OUT/state/<id>.lock), so shards on one filesystem never run a
// task twice; a query whose bake belongs to another shard runs that bake itself when nobody holds it.
#include <filesystem>
#include <iosfwd>
#include <string>

#include "dmgplace/tools/batch/batch_plan.hpp"

namespace dmgplace::tools {

struct BatchOptions {
  std::filesystem::path cli;  // the dmgplace executable the tasks run
  int jobs = 1;               // tasks at a time
  int shard_index = 1, shard_count = 1;
  std::string phase = "all";  // all, bakes, queries (a Slurm array job runs one phase)
  bool dry_run = false;       // list what would run, run nothing
  bool json = false;          // one JSON object per finished task on `out` (for log shippers)
  bool deep = true;           // every bake's output passes `validate --deep` before a query uses it
};

struct BatchTotals {
  int planned = 0;  // tasks in this shard and phase
  int done_before = 0, ran = 0, failed = 0;
};

BatchTotals run_batch(const BatchPlan& plan, const BatchOptions& o, std::ostream& out, std::ostream& progress);

}  // namespace dmgplace::tools
