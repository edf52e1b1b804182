#include "dmgplace/runtime/placement/placement_query.hpp"

#include <cstdio>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {

const char* to_string(PlacementVariant v) {
  switch (v) {
    case PlacementVariant::Full:
      return "full";
    case PlacementVariant::RandomGrasp:
      return "random-grasp";
    case PlacementVariant::NoRegrasp:
      return "no-regrasp";
  }
  return "?";
}

std::optional<PlacementVariant> parse_variant(const std::string& s) {
  for (auto v : {PlacementVariant::Full, PlacementVariant::RandomGrasp, PlacementVariant::NoRegrasp})
    if (s == to_string(v)) return v;
  return std::nullopt;
}

const char* to_string(ObjectiveTerm::Kind k) {
  switch (k) {
    case ObjectiveTerm::Kind::Clearance:
      return "clearance";
    case ObjectiveTerm::Kind::Depth:
      return "depth";
    case ObjectiveTerm::Kind::Distance:
      return "distance";
    case ObjectiveTerm::Kind::Upright:
      return "upright";
  }
  return "?";
}

std::optional<ObjectiveTerm::Kind> parse_objective_kind(const std::string& s) {
  using K = ObjectiveTerm::Kind;
  for (auto k : {K::Clearance, K::Depth, K::Distance, K::Upright})
    if (s == to_string(k)) return k;
  return std::nullopt;
}

const std::vector<PlacementOptionSpec>& placement_option_specs() {
  using O = PlacementOptions;
  static const std::vector<PlacementOptionSpec> specs = {
      {"max_depth", &O::max_depth, 1, 12, "quadtree x theta levels below a region"},
      {"ucb_c", &O::ucb_c, 0, 100, "UCB1 exploration constant"},
      {"goal_iterations", &O::goal_iterations, 1, 100000, "MCTS iterations per goal-sampling call"},
      {"reward_arm_free", &O::reward_arm_free, 0, 1000, "relaxed reward weight: arm collision-free"},
      {"reward_object_free", &O::reward_object_free, 0, 1000, "relaxed reward weight: object collision-free"},
      {"reward_contact", &O::reward_contact, 0, 1000, "relaxed reward weight: stable contact"},
      {"reward_objective", &O::reward_objective, 0, 1000, "relaxed reward weight: objective improves"},
      {"reward_reachable", &O::reward_reachable, 0, 1000, "relaxed reward weight: IK solution exists"},
      {"p_accept", &O::p_accept, 0, 1, "probability of keeping a cached grasp (Algorithm 3)"},
      {"hand_tries", &O::hand_tries, 0, 100000,
       "hand-checked draws outside the grasp cache before an unchecked one (0: the paper's)"},
      {"lift", &O::lift, 0, 0.1, "goal configurations hold the object this far above the support (m)"},
      {"ik_restarts", &O::ik_restarts, 0, 1000, "random IK restarts after the seed"},
      {"motion_resolution", &O::motion_resolution, 1e-4, 1, "joint-space collision check step (rad)"},
      {"threads", &O::threads, 0, 256, "planner worker threads; 0: synchronous and deterministic"},
      {"slice_iterations", &O::slice_iterations, 1, 1000000,
       "synchronous mode: planner iterations per round, shared by the grasps with goals"},
      {"max_open_goals", &O::max_open_goals, 1, 100000, "goal sampling pauses while this many wait for a path"},
      {"share_start_trees", &O::share_start_trees, 0, 0,
       "a new grasp's planner starts from the largest start tree of another grasp, re-checked where used"},
      {"optimize_locally", &O::optimize_locally, 0, 0, "gradient ascent of the objective after each solution"},
      {"local_step", &O::local_step, 1e-6, 1, "initial local-optimisation step (m; rad for theta)"},
      {"local_min_step", &O::local_min_step, 1e-9, 1, "local optimisation stops below this step"},
      {"local_iterations", &O::local_iterations, 0, 100000, "local optimisation steps"},
      {"check_retreat", &O::check_retreat, 0, 0,
       "require a retreat after release: withdraw, then a motion to the retreat configuration"},
      {"release_clearance", &O::release_clearance, 0, 0.1,
       "the fingers open this far beyond the grasp's opening, each, to let go (m)"},
      {"retreat_distance", &O::retreat_distance, 0, 1,
       "longest straight withdrawal of the open hand before the retreat motion (m)"},
      {"retreat_iterations", &O::retreat_iterations, 1, 10000000, "retreat motion: planner iterations per placement"},
      {"retreat_time", &O::retreat_time, 1e-3, 1000, "retreat motion: seconds per placement at most"},
      {"tie_tolerance", &O::tie_tolerance, 0, 1, "objective values this close count as equal"},
      {"velocity_scaling", &O::velocity_scaling, 1e-6, 1,
       "timed trajectories: fraction of the joints' velocity limits"},
      {"acceleration_scaling", &O::acceleration_scaling, 1e-6, 1,
       "timed trajectories: fraction of the joints' acceleration limits"},
  };
  return specs;
}

std::string number_text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

void check_placement_options(const PlacementOptions& o, const std::string& source) {
  for (const auto& s : placement_option_specs()) {
    double v = 0;
    if (const auto* m = std::get_if<int PlacementOptions::*>(&s.member)) v = o.*(*m);
    else if (const auto* d = std::get_if<double PlacementOptions::*>(&s.member)) v = o.*(*d);
    else continue;  // booleans have no range
    if (!(v >= s.lo && v <= s.hi))
      throw Error(source, std::string("options.") + s.name,
                  number_text(v) + " is outside its range [" + number_text(s.lo) + ", " + number_text(s.hi) + "]");
  }
}

}  // namespace dmgplace::runtime
