#pragma once
// Reading a batch folder back: `dmgplace batch-status` (done / failed / pending per task) and
// `dmgplace batch-collect` (one dataset file with a row per query run).
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace dmgplace::tools {

struct BatchStatus {
  struct Entry {
    std::string id, name, kind, state;  // state: done, failed, running, pending
    std::string error;
    double seconds = 0;
  };
  std::vector<Entry> tasks;
  int done = 0, failed = 0, running = 0, pending = 0;
  double eta_seconds = 0;  // pending x mean time of the finished ones (one job)
};

BatchStatus batch_status(const std::filesystem::path& out);
void print_status(const BatchStatus& s, bool json, std::ostream& os);

// DATASET.h5 ("dmgplace.dataset" v1): one row per finished query run. Columns (datasets under
// runs/): task_id, robot, object, environment, grasp, variant (strings), seed, face, grasp_state,
// in_hand_actions, path_waypoints (int64), solved (uint8), objective, first_solution_time,
// seconds (float64, NaN where unsolved), g0 and pose (N x 7: x y z qx qy qz qw); provenance:
// each row's robot/object/environment artifact identities. Returns the number of rows.
std::size_t collect_batch(const std::filesystem::path& out, const std::filesystem::path& dataset);

}  // namespace dmgplace::tools
