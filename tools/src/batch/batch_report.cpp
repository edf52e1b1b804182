#include "dmgplace/tools/batch/batch_report.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "batch_dataset.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_writer.hpp"
#include "dmgplace/tools/batch/batch_state.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;

BatchStatus batch_status(const fs::path& out) {
  const BatchPlan plan = read_plan(out);
  BatchStatus s;
  double finished_seconds = 0;
  for (const auto& t : plan.tasks) {
    BatchStatus::Entry e{t.id, t.name, t.kind, "pending", "", 0};
    std::error_code ec;
    if (const auto r = read_record(out, t.id)) {
      e.seconds = r->seconds;
      e.error = r->error;
      e.state = r->ok ? "done" : "failed";
      finished_seconds += r->seconds;
    }
    if (e.state == "pending" && fs::exists(out / "state" / (t.id + ".lock"), ec)) e.state = "running";
    (e.state == "done" ? s.done : e.state == "failed" ? s.failed : e.state == "running" ? s.running : s.pending)++;
    s.tasks.push_back(std::move(e));
  }
  const int finished = s.done + s.failed;
  s.eta_seconds = finished ? finished_seconds / finished * (s.pending + s.running) : 0;
  return s;
}

void print_status(const BatchStatus& s, bool json, std::ostream& os) {
  if (json) {
    nlohmann::ordered_json tasks = nlohmann::ordered_json::array();
    for (const auto& e : s.tasks)
      tasks.push_back({{"id", e.id},
                       {"name", e.name},
                       {"kind", e.kind},
                       {"state", e.state},
                       {"seconds", e.seconds},
                       {"error", e.error}});
    os << nlohmann::ordered_json{{"done", s.done},       {"failed", s.failed},           {"running", s.running},
                                 {"pending", s.pending}, {"eta_seconds", s.eta_seconds}, {"tasks", tasks}}
              .dump(1)
       << "\n";
    return;
  }
  for (const auto& e : s.tasks)
    if (e.state != "done") os << e.state << "  " << e.name << (e.error.empty() ? "" : ": " + e.error) << "\n";
  os << s.done << " done, " << s.failed << " failed, " << s.running << " running, " << s.pending << " pending of "
     << s.tasks.size() << "; ETA " << std::lround(s.eta_seconds) << " s on one job\n";
}

namespace {

nlohmann::ordered_json read_result(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string(), "", "cannot open");
  std::stringstream ss;
  ss << in.rdbuf();
  auto j = nlohmann::ordered_json::parse(ss.str(), nullptr, false);
  if (j.is_discarded()) throw Error(file.string(), "", "not valid JSON");
  return j;
}

void write_dataset(const fs::path& file, const BatchPlan& plan, const DatasetTables& tables) {
  formats::ArtifactHeader h;
  h.schema = formats::kDatasetSchema;
  h.schema_version = formats::kDatasetSchemaVersion;
  h.parameters_json = nlohmann::json{{"batch", plan.name}, {"rows", tables.runs.rows()}}.dump();
  formats::H5Writer w(file, h);
  for (const auto& [group, table] : tables.all()) write_table(w, group, *table);
  w.commit();
}

}  // namespace

std::size_t collect_batch(const fs::path& out, const CollectOptions& o) {
  if (o.dataset.empty() && o.csv.empty())
    throw Error("batch-collect", "", "nothing to write: give --out DATASET.h5, --csv FILE.csv or both");
  std::error_code ec;
  if (!o.dataset.empty() && !o.csv.empty() && fs::weakly_canonical(o.dataset, ec) == fs::weakly_canonical(o.csv, ec))
    throw Error(o.csv.string(), "", "--csv names the same file as --out");
  const BatchPlan plan = read_plan(out);
  DatasetBuilder builder;
  std::size_t runs = 0;
  for (const auto& t : plan.tasks) {
    if (t.kind != "query" || !task_done(out, t)) continue;
    const fs::path file = t.output / "result.json";
    builder.add_run(t, read_result(file), file.string());
    ++runs;
  }
  if (runs == 0)
    throw Error((out / "batch.json").string(), "",
                "no finished query run to collect yet (`dmgplace batch-status` shows progress)");
  const DatasetTables tables = builder.finish();
  if (!o.dataset.empty()) write_dataset(o.dataset, plan, tables);
  if (!o.csv.empty()) formats::write_file_atomically(o.csv, csv_text(tables.runs));
  return runs;
}

}  // namespace dmgplace::tools
