#pragma once
// What a placement query asks for: start configuration, initial grasp, target volume, objective,
// variant and the algorithm's parameters (defaults from the paper and its authors' code).
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace dmgplace::runtime {

enum class PlacementVariant { Full, RandomGrasp, NoRegrasp };
const char* to_string(PlacementVariant v);
std::optional<PlacementVariant> parse_variant(const std::string& s);  // "full", "random-grasp", "no-regrasp"

// One weighted term of the objective (maximised).
struct ObjectiveTerm {
  enum class Kind {
    Clearance,  // mean clearance of the object's points from obstacles above and to the side (m)
    Depth,      // COM position along `vector` (unit; the paper's "deeper into the shelf")
    Distance,   // minus the COM's distance to the point `vector`
    Upright,    // cosine between the object axis `vector` (object frame) and world z
  };
  Kind kind = Kind::Clearance;
  double weight = 1.0;
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();
};
const char* to_string(ObjectiveTerm::Kind k);
std::optional<ObjectiveTerm::Kind> parse_objective_kind(const std::string& s);  // clearance, depth, distance, upright

struct PlacementOptions {
  // Goal sampling (Algorithm 2).
  int max_depth = 4;         // quadtree x theta levels below a region (smallest theta 2 pi / 4^4)
  double ucb_c = 0.5;        // UCB1 exploration constant
  int goal_iterations = 25;  // i_max: MCTS iterations per goal-sampling call
  // Relaxed rewards of invalid samples (the authors' weights), normalised by their sum.
  double reward_arm_free = 0.1, reward_object_free = 0.15, reward_contact = 0.15, reward_objective = 0.25,
         reward_reachable = 0.2;
  // Grasp selection (Algorithm 3).
  double p_accept = 0.9;  // a cached grasp whose hand fits is taken with this probability
  int hand_tries = 8;     // beyond the paper: hand-checked draws from G(g0) \ G first (0: off)
  // Validity.
  double lift = 0.004;  // goal configurations hold the object this far above the support (m)
  int ik_restarts = 4;  // random restarts after the seed
  // Motion planning.
  double motion_resolution = 0.05;  // joint-space collision check step (rad)
  int threads = 0;                  // 0: synchronous and deterministic; N > 0: N planner worker threads
  int slice_iterations = 200;       // synchronous mode: planner iterations per round, shared by the grasps with goals
  int max_open_goals = 64;          // goal sampling pauses while this many wait for a path
  bool share_start_trees = true;    // a new grasp's planner starts from the start tree another grasp grew
  // Local optimisation (OPTIMIZELOCALLY).
  bool optimize_locally = true;
  double local_step = 0.01;  // initial step of the object along the gradient (m; rad for theta)
  double local_min_step = 0.0005;
  int local_iterations = 100;
  // Beyond the paper.
  // The retreat after release: the fingers open by release_clearance each beyond the grasp's
  // opening (at most the gripper's maximum), the open hand withdraws along -approach (else up)
  // until it clears the object, at most retreat_distance, then an arm motion to the query's
  // retreat_configuration (q0 when unset) with the object an obstacle. A placement without one
  // within the budget (retreat_iterations planner iterations, at most retreat_time s) is dropped.
  bool check_retreat = true;
  double release_clearance = 0.01;  // m per finger
  double retreat_distance = 0.08;   // m
  int retreat_iterations = 5000;
  double retreat_time = 1.0;    // s
  double tie_tolerance = 1e-4;  // objective values this close count as equal: fewer in-hand actions win
  // Timed trajectories of every path returned: fractions of the robot's velocity and
  // acceleration limits (MoveIt's scaling factors).
  double velocity_scaling = 1.0;
  double acceleration_scaling = 1.0;
};

// One line per option: its name in query files, where it lives, its range and what it means. The
// query reader, the planner's own check and the documentation all read this table, so a range
// is written once.
struct PlacementOptionSpec {
  const char* name;
  std::variant<int PlacementOptions::*, double PlacementOptions::*, bool PlacementOptions::*> member;
  double lo = 0, hi = 0;  // inclusive; unused for booleans
  const char* help = "";
};
const std::vector<PlacementOptionSpec>& placement_option_specs();
// Throws dmgplace::Error naming `source` (the query file, or "query"), the option and its range.
// Ranges in messages are printed with number_text (shortest form, "1e+06", "0.1").
std::string number_text(double v);
void check_placement_options(const PlacementOptions& o, const std::string& source);

// A second arm that performs the in-hand actions as the paper executes them: the grasping arm
// holds q0 while the pusher's tool pushes the object in the closed gripper (PlacementSolution::pushes).
struct PusherSpec {
  std::string base, tip;  // the pusher's chain; base is the grasping arm's base or rigid with it
  Eigen::Isometry3d tcp =
      Eigen::Isometry3d::Identity();  // the tool's contact point in the tip frame, z the push direction
  double standoff = 0.03;             // m: the tool starts and ends each push this far from the object
  double step = 0.005;                // m: Cartesian step of the pushes, each solved by IK
  double plan_time = 0.5;             // s: budget of each free motion to and from a push
  int plan_iterations = 3000;         // and its planner iterations (deterministic runs end on these)
};

struct PlacementQuery {
  Eigen::VectorXd q0;                                    // arm chain joints, the kinematics' order
  Eigen::Isometry3d g0 = Eigen::Isometry3d::Identity();  // initial grasp: TCP pose in the object frame
  std::optional<double> g0_opening;                      // m; unset: the grasp graph's own
  std::optional<Eigen::AlignedBox3d> volume;             // target volume; unset: the environment's
  std::optional<Eigen::VectorXd> retreat_configuration;  // where the arm retreats to; unset: q0
  // Plans each in-hand action for this arm; unset: the actions are reported for a second arm or a
  // fixture to perform. The pusher starts and ends at its joints' values in the world.
  std::optional<PusherSpec> pusher;
  std::vector<ObjectiveTerm> objective{ObjectiveTerm{}};
  PlacementVariant variant = PlacementVariant::Full;
  std::uint64_t seed = 1;
  PlacementOptions options;
  std::string source = "query";  // where the query came from (its file), named in every error about it
};

}  // namespace dmgplace::runtime
