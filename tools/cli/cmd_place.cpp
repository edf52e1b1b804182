#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>

#include "cli_log.hpp"
#include "commands.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime.hpp"
#include "dmgplace/tools/placement/placement_report.hpp"

namespace dmgplace::cli {

int run_place(const PlaceArgs& a) {
  tools::PlacementQueryFile q = tools::read_placement_query(a.query, a.artifacts, a.allow_outside);
  if (a.time_limit) q.time_limit = *a.time_limit;
  if (a.seed) q.query.seed = *a.seed;
  if (a.threads) q.query.options.threads = *a.threads;
  if (!a.variant.empty()) {
    const auto v = runtime::parse_variant(a.variant);
    if (!v) throw Error("--variant", "", "unknown variant '" + a.variant + "' (full, random-grasp, no-regrasp)");
    q.query.variant = *v;
  }
  if (a.pusher == "none") q.query.pusher.reset();
  else if (!a.pusher.empty())
    throw Error("--pusher", a.pusher, "expected 'none' (the pusher arm is named in the query file)");
  const auto t_load = std::chrono::steady_clock::now();
  auto robot = formats::load_robot(q.robot);
  const auto joints = tools::world_joint_values(q, robot.model);
  const auto world = World::from_artifacts(std::move(robot), formats::load_object(q.object),
                                           formats::load_environment(q.environment), q.query.g0_opening, joints);
  q.query.q0 = tools::resolve_start(q, world->kinematics());
  const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();
  std::ostringstream loaded;
  loaded << "loaded " << q.robot.filename().string() << ", " << q.object.filename().string() << ", "
         << q.environment.filename().string() << " in " << load_s << " s; variant "
         << runtime::to_string(q.query.variant) << ", seed " << q.query.seed << ", " << q.time_limit << " s";
  log_info(loaded.str());
  const auto timer = stop_after_seconds(q.time_limit);
  const auto rounds = a.iterations > 0 ? stop_after_iterations(a.iterations) : StopCondition();
  const auto deadline = [&] { return (rounds && rounds()) || timer(); };
  // Progress on stderr every few seconds; improvements on stdout as they come.
  auto last = std::chrono::steady_clock::now();
  const auto stop = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last).count() >= 5) {
      last = now;
      log_info("  ... still searching");
    }
    return deadline();
  };
  const auto result = place(*world, q.query, stop, [&](const runtime::PlacementSolution& s) {
    std::cout << tools::solution_line(s) << std::endl;
  });
  if (result.solved()) {
    const auto& b = result.best();
    std::cout << "best: objective " << b.objective << " after " << b.time << " s with grasp " << b.grasp_state << " ("
              << b.in_hand.size() << " in-hand actions from g0); " << result.improvements.size() << " improvements, "
              << result.counters.samples << " samples, " << result.counters.goals << " goals in " << result.seconds
              << " s\n";
    for (std::size_t i = 0; i < b.in_hand.size(); ++i) {
      const auto& act = b.in_hand[i];
      std::cout << "  in-hand " << i + 1 << ": "
                << (act.type == runtime::GraspMove::Translation
                        ? "push " + std::to_string(act.distance * 1000) + " mm"
                        : "rotate " + std::to_string(act.angle * 180 / M_PI) + " deg")
                << " (state " << act.from_state << " -> " << act.to_state << ")\n";
    }
    std::cout << "  trajectory " << b.trajectory.duration() << " s to the placement, retreat "
              << b.retreat_trajectory.duration() << " s\n";
    for (const auto& p : b.pushes)
      std::cout << "  push " << p.action + 1 << ": the pusher touches the object at (" << p.contact.x() << ", "
                << p.contact.y() << ", " << p.contact.z() << "), " << p.trajectory.duration() << " s\n";
    if (!b.in_hand.empty() && b.pushes.empty())
      std::cout
          << "  the in-hand actions need a second arm or a fixture to push the object: not planned for execution\n";
  } else {
    std::cout << "no solution: " << result.reason << "\n";
  }
  const std::filesystem::path out =
      a.out.empty() ? std::filesystem::path("place-" + q.path.stem().string()) : std::filesystem::path(a.out);
  tools::write_placement_result(out, q, result, world->kinematics(),
                                tools::parse_trajectory_format(a.trajectory_format, "--trajectory-format"));
  if (a.json) std::cout << tools::result_json(q, result, world->kinematics());
  log_info("wrote " + (out / "result.json").string() + ", trace.csv, path.csv, trajectory.json" +
           (a.trajectory_format == "moveit" ? ", trajectory_approach.yaml, trajectory_retreat.yaml" : ""));
  return result.solved() ? 0 : 3;
}

}  // namespace dmgplace::cli
