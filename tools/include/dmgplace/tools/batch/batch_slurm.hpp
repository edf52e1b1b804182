#pragma once
// `dmgplace batch --slurm`: two sbatch array jobs, one array task per shard. The bakes run first;
// the queries' array depends on them (--dependency=afterok). Scripts go to OUT/slurm/.
#include <filesystem>
#include <string>

namespace dmgplace::tools {

struct SlurmOptions {
  std::filesystem::path cli, manifest, out;
  int array_size = 4;     // shards
  std::string partition;  // empty: the cluster's default
  std::string time;       // HH:MM:SS per array task; empty: the partition's default
  std::string sbatch = "sbatch";
  bool deep = true;  // false: the bakes skip `validate --deep` (batch --no-deep)
};

struct SlurmSubmission {
  std::filesystem::path bakes_script, queries_script;
  std::string bakes_job, queries_job;  // job ids sbatch returned
};

// Writes both scripts (paths single-quoted: nothing in a name is run) and, when `submit`, runs
// sbatch on them (argv, no shell). dmgplace::Error with sbatch's message when it refuses.
SlurmSubmission submit_slurm(const SlurmOptions& o, bool submit = true);

}  // namespace dmgplace::tools
