#include <iostream>
#include <regex>

#include <sstream>

#include "cli_log.hpp"
#include "commands.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/batch/batch_manifest.hpp"
#include "dmgplace/tools/batch/batch_plan.hpp"
#include "dmgplace/tools/batch/batch_report.hpp"
#include "dmgplace/tools/batch/batch_runner.hpp"
#include "dmgplace/tools/batch/batch_slurm.hpp"

namespace dmgplace::cli {

int run_batch(const BatchArgs& a) {
  std::smatch m;
  if (!std::regex_match(a.shard, m, std::regex("([0-9]{1,6})/([0-9]{1,6})")) || std::stoi(m[1]) < 1 ||
      std::stoi(m[1]) > std::stoi(m[2]))
    throw Error("--shard", "", "expected I/N with 1 <= I <= N, got '" + a.shard + "'");
  const auto cli = std::filesystem::read_symlink("/proc/self/exe");
  const auto out = std::filesystem::absolute(a.out);
  const auto manifest = std::filesystem::absolute(a.manifest);
  const auto plan = tools::plan_batch(tools::read_batch_manifest(manifest), out);
  if (a.slurm) {
    tools::SlurmOptions so{cli, manifest, out, a.array_size, a.partition, a.time};
    so.deep = !a.no_deep;
    const auto s = tools::submit_slurm(so, !a.dry_run);
    std::cout << "wrote " << s.bakes_script.string() << " and " << s.queries_script.string() << "\n";
    if (!a.dry_run) std::cout << "submitted: bakes " << s.bakes_job << ", queries " << s.queries_job << " (afterok)\n";
    return 0;
  }
  tools::BatchOptions o;
  o.cli = cli;
  o.jobs = a.jobs;
  o.shard_index = std::stoi(m[1]);
  o.shard_count = std::stoi(m[2]);
  o.phase = a.phase;
  o.dry_run = a.dry_run;
  o.json = a.json;
  o.deep = !a.no_deep;
  const auto t = tools::run_batch(plan, o, std::cout, progress_stream());
  std::ostringstream summary;
  summary << t.ran << " ran, " << t.failed << " failed, " << t.done_before << " were done; `dmgplace batch-status "
          << out.string() << "` lists the failures";
  log_info(summary.str());
  return t.failed ? 1 : 0;
}

int run_batch_status(const BatchStatusArgs& a) {
  const auto s = tools::batch_status(a.dir);
  tools::print_status(s, a.json, std::cout);
  return s.failed ? 1 : 0;
}

int run_batch_collect(const BatchCollectArgs& a) {
  const auto rows = tools::collect_batch(a.dir, {a.out, a.csv});
  for (const auto& file : {a.out, a.csv})
    if (!file.empty()) std::cout << "wrote " << file << ": " << rows << " runs\n";
  return 0;
}

}  // namespace dmgplace::cli
