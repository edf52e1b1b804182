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

// DATASET.h5 ("dmgplace.dataset" v2, checksummed like the artifacts; docs/batch.md). Each group is
// a table: 1-D columns of equal length, listed in the order written, so pandas makes a DataFrame of
// one in one call: pd.DataFrame({k: c[()] for k, c in f["runs"].items()}). Strings are fixed-length
// UTF-8 (h5py gives numpy bytes; `.asstr()` gives str). Float columns hold NaN where a row has no
// value. `run` is a row of runs/; runs come in plan order.
//   runs/     one row per finished query run: task_id, robot, object, environment, grasp, variant,
//             seed, robot_artifact, object_artifact, environment_artifact (identities), g0_x ...
//             g0_qw, solved, reason ("" when solved), seconds, improvements, reachable_grasps,
//             initial_state, snap_distance, initial_opening, dof; of the best solution (NaN, -1 or 0
//             when unsolved): objective, first_solution_time, solution_time, face, region,
//             grasp_state, opening, grasp_cost, in_hand_actions, path_waypoints, retreat_waypoints,
//             release_opening, duration, retreat_duration, pose_x ... pose_qw; then the run's
//             counters, one column each, named as in result.json's `counters`.
//   path/     one row per waypoint of the best solution's arm path (result.json best.path): run,
//             step, q0 ... (one per joint of the widest robot; NaN beyond a run's dof).
//   retreat/  the same for best.retreat.
//   actions/  one row per in-hand action (best.in_hand): run, step, type (push or rotate),
//             from_state, to_state, distance, push_direction_x/y/z (push), angle, axis_x/y/z,
//             pivot_x/y/z (rotate).
//   fingers/  one row per finger waypoint of an action: run, action (a row of actions/), finger
//             (1 or 2), step, x, y, z.
//   trace/    one row per improvement (the objective trace): run, step, time, objective, face,
//             region, grasp_state, in_hand_actions, pose_x ... pose_qw, counters when it was found.
//   joints/   one row per joint of each robot in runs/: robot, index (k of column qk), name.
//   offsets/  runs + 1 rows, columns path, retreat, actions, fingers, trace: run i's rows of table T
//             are offsets/T[i] up to offsets/T[i + 1] (ragged arrays without a group-by).
struct CollectOptions {
  std::filesystem::path dataset;  // DATASET.h5; empty: none
  std::filesystem::path csv;      // runs/ as CSV (header row, RFC 4180 quoting); empty: none
};
// Writes what `o` names; returns the number of runs. Throws dmgplace::Error naming the file and
// field of a bad result.json, and when no query run has finished.
std::size_t collect_batch(const std::filesystem::path& out, const CollectOptions& o);

}  // namespace dmgplace::tools
