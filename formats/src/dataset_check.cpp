// `batch-collect`'s dataset files, checked beyond their checksums.
#include "dataset_check.hpp"

#include <map>
#include <optional>

#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_reader.hpp"

namespace dmgplace::formats::detail {
namespace {

// `batch-collect`'s dataset (batch_report.hpp): tables of equal-length 1-D columns, linked by
// their `run` columns and offsets/.
struct DatasetTableSpec {
  const char* name;
  std::vector<const char*> strings, numbers;  // the columns every dataset of this version has
};

const std::vector<DatasetTableSpec>& dataset_tables() {
  static const std::vector<DatasetTableSpec> tables{
      {"runs",
       {"task_id", "robot", "object", "environment", "grasp", "variant", "robot_artifact", "object_artifact",
        "environment_artifact", "reason"},
       {"seed", "solved", "seconds", "improvements", "dof", "objective", "first_solution_time", "solution_time", "face",
        "region", "grasp_state", "in_hand_actions", "path_waypoints", "retreat_waypoints", "g0_x", "g0_qw", "pose_x",
        "pose_qw"}},
      {"path", {}, {"run", "step"}},
      {"retreat", {}, {"run", "step"}},
      {"actions", {"type"}, {"run", "step", "from_state", "to_state", "distance", "angle"}},
      {"fingers", {}, {"run", "action", "finger", "step", "x", "y", "z"}},
      {"trace", {}, {"run", "step", "time", "objective", "face", "grasp_state"}},
      {"joints", {"robot", "name"}, {"index"}},
      {"offsets", {}, {"path", "retreat", "actions", "fingers", "trace"}}};
  return tables;
}

// The table's row count; a missing column, a column of another length or shape is a problem.
std::size_t check_dataset_table(const H5Reader& r, const DatasetTableSpec& spec, std::vector<std::string>& problems) {
  const std::string group = std::string(spec.name) + "/";
  std::optional<std::size_t> rows;
  for (const auto& name : r.dataset_names()) {
    if (name.rfind(group, 0) != 0) continue;
    const auto dims = r.shape(name);
    if (dims.size() != 1) problems.push_back(Error(r.file(), name, "a table column must be 1-D").what());
    else if (rows && dims[0] != *rows)
      problems.push_back(
          Error(r.file(), name, "has " + std::to_string(dims[0]) + " rows, the table " + std::to_string(*rows)).what());
    else rows = dims[0];
  }
  for (const auto& columns : {spec.strings, spec.numbers})
    for (const char* c : columns)
      if (!r.has(group + c)) problems.push_back(Error(r.file(), group + c, "missing column").what());
  for (const char* c : spec.strings)
    if (r.has(group + c)) r.read_utf8_strings(group + c);  // throws unless UTF-8 strings
  return rows.value_or(0);
}

// Run i's rows of `table` are offsets/<table>[i] .. [i + 1], their `run` is i, and runs/<count>
// (when given) says how many there are.
void check_dataset_links(const H5Reader& r, const std::string& table, std::size_t runs, std::size_t rows,
                         const char* count, std::vector<std::string>& problems) {
  const auto offsets = r.read_i64("offsets/" + table, {long(runs + 1)}).data;
  const auto run = r.read_i64(table + "/run", {long(rows)}).data;
  const auto counts = count ? r.read_i64(std::string("runs/") + count, {long(runs)}).data : std::vector<std::int64_t>();
  if (offsets.front() != 0 || offsets.back() != std::int64_t(rows))
    return problems.push_back(Error(r.file(), "offsets/" + table, "does not span the table's rows").what());
  for (std::size_t i = 0; i < runs; ++i) {
    if (offsets[i + 1] < offsets[i] || (count && counts[i] != offsets[i + 1] - offsets[i]))
      return problems.push_back(Error(r.file(), "offsets/" + table, "disagrees at run " + std::to_string(i)).what());
    for (auto k = offsets[i]; k < offsets[i + 1]; ++k)
      if (run[std::size_t(k)] != std::int64_t(i))
        return problems.push_back(
            Error(r.file(), table + "/run", "row " + std::to_string(k) + " is not run " + std::to_string(i)).what());
  }
}

}  // namespace

std::vector<std::string> check_dataset(const std::filesystem::path& path) {
  try {
    H5Reader r(path);
    if (r.header().schema_version != kDatasetSchemaVersion)
      return {Error(r.file(), "schema_version",
                    "is " + std::to_string(r.header().schema_version) + ", this build reads version " +
                        std::to_string(kDatasetSchemaVersion) + " (collect it again with `dmgplace batch-collect`)")
                  .what()};
    std::vector<std::string> problems;
    std::map<std::string, std::size_t> rows;
    for (const auto& spec : dataset_tables()) rows[spec.name] = check_dataset_table(r, spec, problems);
    if (!problems.empty()) return problems;
    const std::size_t runs = rows["runs"];
    for (auto [table, count] : {std::pair<const char*, const char*>{"path", "path_waypoints"},
                                {"retreat", "retreat_waypoints"},
                                {"actions", "in_hand_actions"},
                                {"fingers", nullptr},
                                {"trace", "improvements"}})
      check_dataset_links(r, table, runs, rows[table], count, problems);
    for (auto a : r.read_i64("fingers/action", {-1}).data)
      if (a < 0 || std::size_t(a) >= rows["actions"])
        return {Error(r.file(), "fingers/action", "names no row of actions/").what()};
    return problems;
  } catch (const Error& e) {
    return {e.what()};
  }
}

}  // namespace dmgplace::formats::detail
