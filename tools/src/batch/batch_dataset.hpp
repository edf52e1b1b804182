#pragma once
// The tables of `batch-collect`'s dataset (layout: batch_report.hpp), filled one run at a time from
// the plan's task and the run's result.json.
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "dataset_table.hpp"
#include "dmgplace/tools/batch/batch_plan.hpp"

namespace dmgplace::tools {

struct DatasetTables {
  DatasetTable runs, path, retreat, actions, fingers, trace, joints, offsets;
  // Every table as (group name, table), in the order they are written.
  std::vector<std::pair<std::string, const DatasetTable*>> all() const;
};

class DatasetBuilder {
 public:
  DatasetBuilder();
  // One finished query run; a missing or mistyped field of `result` throws dmgplace::Error naming
  // `file` and the field (e.g. best/in_hand/2/angle).
  void add_run(const BatchTask& task, const nlohmann::ordered_json& result, const std::string& file);
  // Closes the offsets and joints tables; the builder is spent.
  DatasetTables finish();

 private:
  void add_offsets_row();
  std::size_t robot_dof(const std::string& robot, const nlohmann::ordered_json& result, const std::string& file);
  DatasetTables t_;
  bool counters_known_ = false;
  std::vector<std::string> counter_names_;                                     // the first run's, in its order
  std::vector<std::pair<std::string, std::vector<std::string>>> joint_names_;  // per robot, first seen first
};

}  // namespace dmgplace::tools
