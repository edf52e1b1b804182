// Places the built-in bottle, held top-down, deep onto the cabinet's lower shelf (the artifacts
// `scripts/demo` bakes into out/demo/artifacts): usage `place_example ARTIFACT_DIR [SECONDS]`.
#include <cstdio>
#include <cstdlib>
#include <dmgplace/runtime.hpp>
#include <filesystem>

int main(int argc, char** argv) try {
  if (argc < 2) return std::fprintf(stderr, "usage: %s ARTIFACT_DIR [SECONDS]\n", argv[0]), 2;
  const std::filesystem::path dir = argv[1];
  const auto world = dmgplace::World::load(dir / "dmgarm.h5", dir / "bottle.h5", dir / "cabinet.h5");
  dmgplace::runtime::PlacementQuery query;
  query.q0 = Eigen::VectorXd(world->dof());
  query.q0 << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;  // dmgarm's home
  query.g0 =
      Eigen::Translation3d(0, 0, 0.13) * Eigen::Quaterniond(0, 1, 0, 0);  // TCP above the bottle, approaching down
  query.volume = Eigen::AlignedBox3d(Eigen::Vector3d(0.62, -0.07, 0.45), Eigen::Vector3d(0.85, 0.39, 0.72));
  const double seconds = argc > 2 ? std::atof(argv[2]) : 5.0;
  const auto result = dmgplace::place(
      *world, query, dmgplace::stop_after_seconds(seconds), [](const dmgplace::runtime::PlacementSolution& s) {
        std::printf("  %.3f s: objective %.4f with grasp %d\n", s.time, s.objective, s.grasp_state);
      });
  if (!result.solved()) return std::printf("no solution: %s\n", result.reason.c_str()), 3;
  const auto& best = result.best();
  std::printf("solved: objective %.6f, grasp %d after %zu in-hand actions, arm path of %zu waypoints\n", best.objective,
              best.grasp_state, best.in_hand.size(), best.path.size());
  return 0;
} catch (const dmgplace::Error& e) {
  std::fprintf(stderr, "error: %s\n", e.what());
  return 1;
}
