#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli_log.hpp"
#include "commands.hpp"
#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/motion/arm_timing.hpp"
#include "dmgplace/tools/motion/arm_problem.hpp"
#include "dmgplace/tools/motion/trajectory_files.hpp"

namespace dmgplace::cli {

int run_plan(const PlanArgs& a) {
  const bool moveit =
      tools::parse_trajectory_format(a.trajectory_format, "--trajectory-format") == tools::TrajectoryFormat::MoveIt;
  if (moveit && a.out.empty()) throw Error("--trajectory-format", "moveit", "needs --out (the YAML goes beside it)");
  tools::ArmProblemOptions opt;
  opt.sdf_resolution = a.sdf_resolution;
  auto problem = tools::load_arm_problem(a.robot, a.scene, a.request, opt);
  log_info(problem.sdf ? "scene setup: " + std::to_string(problem.setup_seconds) + " s, of it the distance field " +
                             std::to_string(problem.bake_seconds) + " s"
                       : "scene setup: " + std::to_string(problem.setup_seconds) +
                             " s (its primitives serve: no distance field)");
  auto ours = tools::plan_ours(problem, a.time_limit, a.resolution, a.seed);
  nlohmann::ordered_json j;
  j["solved"] = ours.solved;
  j["valid"] = ours.valid;
  j["seconds"] = ours.seconds;
  j["length"] = ours.length;
  const auto& c = problem.checker->counters();
  j["state_checks"] = c.fast.load();
  j["exact_pair_checks"] = c.exact_pairs.load();
  j["exact_full_checks"] = c.exact_full.load();
  j["proven_collisions"] = c.proven_collisions.load();
  j["joint_names"] = problem.kin->joint_names();  // the order of every waypoint's values
  j["waypoints"] = ours.path;
  runtime::Trajectory timed;
  if (ours.solved)
    timed = runtime::time_arm_path(*problem.kin, ours.path, {a.velocity_scaling, a.acceleration_scaling});
  j["trajectory"] = nlohmann::ordered_json::parse(tools::trajectory_json_text(timed));
  std::cout << (ours.solved ? (ours.valid ? "solved" : "solved but INVALID") : "no solution") << " in "
            << ours.seconds * 1e3 << " ms, " << ours.path.size() << " waypoints, joint-space length " << ours.length
            << "\n"
            << "state checks: " << c.fast.load() << " (" << c.exact_pairs.load() << " needed FCL on flagged links, "
            << c.exact_full.load() << " a full FCL check, " << c.proven_collisions.load()
            << " proved colliding by the spheres' inner balls)\n";
  if (ours.solved) std::cout << "trajectory: " << timed.duration() << " s, " << timed.time.size() << " points\n";
  if (!a.out.empty()) {
    formats::write_file_atomically(a.out, j.dump(2) + "\n");
    std::cout << "wrote " << a.out << "\n";
  }
  if (moveit) {
    const std::filesystem::path yaml = std::filesystem::path(a.out).replace_extension(".trajectory.yaml");
    formats::write_file_atomically(yaml, tools::moveit_trajectory_yaml(timed, problem.kin->joint_names()));
    std::cout << "wrote " << yaml.string() << "\n";
  }
  return ours.solved && ours.valid ? 0 : 3;
}

}  // namespace dmgplace::cli
