#include "dmgplace/tools/batch/batch_slurm.hpp"

#include <regex>
#include <sstream>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/system/process.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;
namespace {

// One word for bash, whatever it holds.
std::string sh_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string script(const SlurmOptions& o, const std::string& phase) {
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# dmgplace batch, " << phase << ": one array task per shard (written by `dmgplace batch --slurm`).\n"
    << "#SBATCH --job-name=dmgplace-" << phase << "\n"
    << "#SBATCH --array=1-" << o.array_size << "\n"
    << "#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --output=" << (o.out / "slurm" / (phase + "-%a.log")).string() << "\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  if (!o.time.empty()) s << "#SBATCH --time=" << o.time << "\n";
  s << "exec " << sh_quote(o.cli.string()) << " batch " << sh_quote(o.manifest.string()) << " --out "
    << sh_quote(o.out.string()) << " --phase " << phase << " --shard \"${SLURM_ARRAY_TASK_ID}/" << o.array_size << "\""
    << (o.deep ? "" : " --no-deep") << "\n";
  return s.str();
}

std::string submit(const SlurmOptions& o, const fs::path& file, const std::vector<std::string>& extra) {
  std::vector<std::string> argv{o.sbatch, "--parsable"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  argv.push_back(file.string());
  ProcessOptions po;
  po.stderr_to = StderrTo::capture;
  const auto r = run_process(argv, po);
  if (r.exit_code != 0)
    throw Error(file.string(), "sbatch", "refused (exit " + std::to_string(r.exit_code) + "): " + r.error_output);
  const std::string id = r.output.substr(0, r.output.find_first_of(";\n"));
  if (!std::regex_match(id, std::regex("[0-9]+")))
    throw Error(file.string(), "sbatch", "no job id in its answer: " + r.output);
  return id;
}

}  // namespace

SlurmSubmission submit_slurm(const SlurmOptions& o, bool do_submit) {
  if (o.array_size < 1 || o.array_size > 100000) throw Error("--array-size", "", "must be in [1, 100000]");
  if (!o.time.empty() && !std::regex_match(o.time, std::regex("([0-9]+-)?[0-9]{1,3}:[0-5][0-9]:[0-5][0-9]")))
    throw Error("--time", "", "expected HH:MM:SS (or D-HH:MM:SS), got '" + o.time + "'");
  if (!o.partition.empty() && !std::regex_match(o.partition, std::regex("[A-Za-z0-9._-]+")))
    throw Error("--partition", "", "expected a partition name, got '" + o.partition + "'");
  fs::create_directories(o.out / "slurm");
  SlurmSubmission s;
  s.bakes_script = o.out / "slurm" / "bakes.sbatch";
  s.queries_script = o.out / "slurm" / "queries.sbatch";
  formats::write_file_atomically(s.bakes_script, script(o, "bakes"));
  formats::write_file_atomically(s.queries_script, script(o, "queries"));
  if (!do_submit) return s;
  s.bakes_job = submit(o, s.bakes_script, {});
  s.queries_job = submit(o, s.queries_script, {"--dependency=afterok:" + s.bakes_job});
  return s;
}

}  // namespace dmgplace::tools
