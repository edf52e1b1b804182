// Loads libompl first (a state space, sampled), then runs a dmgplace placement in the same process.
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cstdio>
#include <dmgplace/runtime.hpp>

int main(int argc, char** argv) try {
  if (argc < 2) return 2;
  auto space = std::make_shared<ompl::base::RealVectorStateSpace>(3);
  space->setBounds(-1, 1);
  auto sampler = space->allocDefaultStateSampler();
  auto* state = space->allocState();
  sampler->sampleUniform(state);
  space->freeState(state);
  const std::filesystem::path dir = argv[1];
  const auto world = dmgplace::World::load(dir / "dmgarm.h5", dir / "bottle.h5", dir / "cabinet.h5");
  dmgplace::runtime::PlacementQuery q;
  q.q0 = Eigen::VectorXd(world->dof());
  q.q0 << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  q.g0 = Eigen::Translation3d(0, 0, 0.06) * Eigen::Quaterniond(0.7071068, 0, 0.7071068, 0);  // side grasp
  const auto r = dmgplace::place(*world, q, dmgplace::stop_after_seconds(5));
  std::printf(r.solved() ? "solved: objective %.6f\n" : "no solution\n", r.solved() ? r.best().objective : 0.0);
  return r.solved() ? 0 : 3;
} catch (const dmgplace::Error& e) {
  std::fprintf(stderr, "error: %s\n", e.what());
  return 1;
}
