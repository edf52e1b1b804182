#pragma once
// One plain function per subcommand; the command line itself (CLI11) lives only in main.cpp.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dmgplace/tools/environment/bake_environment.hpp"
#include "dmgplace/tools/object/dmg_builder.hpp"
#include "dmgplace/tools/robot/allowed_collisions.hpp"
#include "dmgplace/tools/robot/self_distance_tables.hpp"
#include "dmgplace/tools/robot/sphere_cover.hpp"
#include "dmgplace/tools/object/placement_faces.hpp"
#include "dmgplace/tools/scan/scan_segmentation.hpp"
#include "dmgplace/tools/scan/surface_reconstruction.hpp"
#include "option_table.hpp"

namespace dmgplace::cli {

struct ValidateArgs {
  std::vector<std::string> files;
  bool quiet = false, json = false, set = false, check_inputs = false, deep = false;
  int samples = 1000;
  std::uint64_t seed = 1;
};
int run_validate(const ValidateArgs& a);

struct InspectArgs {
  std::string file;
  bool json = false;
};
int run_inspect(const InspectArgs& a);

struct BakeObjectArgs {
  std::vector<std::string> inputs;  // one mesh, or one or more PCD scans of the object
  std::string out;
  bool json = false;
  double scale = 1.0;
  std::string com_text;  // "x,y,z": overrides the computed center of mass
  double mass = 0;       // <= 0: from volume at 1000 kg/m^3
  std::string gripper;   // YAML; empty: the built-in dmgarm hand
  tools::DmgOptions dmg;
  tools::FaceOptions faces;
  double rotation_weight = 0.1;  // grasp graph: cost of in-hand rotation (m per rad)
  // Scans only.
  std::string crop_text, near_text;  // "x0,y0,z0,x1,y1,z1" / "x,y,z"
  tools::ScanSegmentOptions segment;
  std::string support_plane = "auto";
  tools::ReconstructOptions reconstruct;
  std::string reconstruct_method = "poisson";
  std::string dmg_from = "mesh";  // mesh: patches of the reconstructed surface; points: supervoxels of the scan
  // Every option above as a row (option_table.hpp): CLI binding and header parameters in one place.
  OptionTable options();
};
int run_bake_object(const BakeObjectArgs& a);

struct GraspsArgs {
  std::string object;
  std::array<double, 7> initial{};  // TCP pose in the object frame: x y z qx qy qz qw
  std::optional<double> opening;    // unset: not used when snapping
  bool json = false;
};
int run_grasps(const GraspsArgs& a);

struct BakeEnvArgs {
  std::string scene, out;
  bool json = false;
  std::string volume_text, frame_text;  // "xmin,...,zmax" / "x,y,z,roll,pitch,yaw"
  std::vector<std::string> package_paths;
  tools::EnvironmentBakeOptions bake;
  OptionTable options();  // every option as a row (option_table.hpp)
};
int run_bake_env(const BakeEnvArgs& a);

struct BakeRobotArgs {
  std::string urdf, srdf, arm, out;
  std::string joint_limits;  // MoveIt joint_limits.yaml
  bool json = false;
  std::string tcp_text;  // TCP pose on the tip: x,y,z,qx,qy,qz,qw
  std::vector<std::string> package_paths;
  std::string write_srdf;    // without --srdf: write the computed allowed pairs here
  std::string fixed_joints;  // name=value,... joints outside the chain frozen there
  tools::SphereCoverOptions spheres;
  double self_table_step = 0.02;  // radians between self-distance table nodes (0: none)
  tools::SelfTableOptions self_tables;
  int threads = 0;  // 0: every CPU the process may use (its affinity mask)
  tools::AllowedCollisionOptions allowed;
  OptionTable options();  // every option as a row (option_table.hpp)
};
int run_bake_robot(const BakeRobotArgs& a);

struct PlanArgs {
  std::string scene, request, robot, out;
  double time_limit = 10, resolution = 0.01, sdf_resolution = 0.02;
  double velocity_scaling = 1, acceleration_scaling = 1;
  std::string trajectory_format = "json";  // json or moveit
  std::uint64_t seed = 1;
};
int run_plan(const PlanArgs& a);

struct BenchMbmArgs {
  std::vector<std::string> dirs;
  std::string robot, csv;
  std::string planners = "both";     // ours, stock or both
  std::string stock_bvh = "obbrss";  // the baseline's FCL mesh BVHs: obbrss (MoveIt's) or obb
  std::string field = "auto";        // ours: auto (none for a scene of few primitives) or always
  int runs = 1, limit = 0;
  double time_limit = 10, resolution = 0.01, sdf_resolution = 0.02;
};
int run_bench_mbm(const BenchMbmArgs& a);

struct PlaceArgs {
  std::string query, out;  // out empty: ./place-<query stem>
  std::string artifacts;   // folder for the query's relative artifact paths; empty: the query's folder
  std::optional<double> time_limit;
  std::optional<std::uint64_t> seed;
  std::optional<int> threads;
  long iterations = 0;  // > 0: also stop after this many search rounds (reproducible runs)
  std::string variant;  // empty: the query's
  std::string pusher;   // empty: the query's; "none": no pusher
  bool json = false;
  bool allow_outside = false;              // artifact paths may leave the artifact folder
  std::string trajectory_format = "json";  // json or moveit
};
int run_place(const PlaceArgs& a);

struct ExperimentArgs {
  std::string spec, out, artifacts;
  int runs = 0, jobs = 1;
  bool quick = false;
  std::optional<double> time_limit;
};
int run_experiment(const ExperimentArgs& a);

struct PlotArgs {
  std::string dir;
};
int run_plot(const PlotArgs& a);

struct ViewArgs {
  std::string result_dir;  // a `dmgplace place` output folder (result.json)
  std::string html;        // output HTML file
  std::string artifacts;   // where the result's artifacts are, when moved; empty: the paths in result.json
};
int run_view(const ViewArgs& a);

struct MakeObjectsArgs {
  std::string out_dir;
};
int run_make_objects(const MakeObjectsArgs& a);

struct BatchArgs {
  std::string manifest, out, shard = "1/1", phase = "all";
  int jobs = 1;
  bool keep_going = true, dry_run = false, json = false;
  bool no_deep = false;
  bool slurm = false;
  std::string partition, time;
  int array_size = 4;
};
int run_batch(const BatchArgs& a);
struct BatchStatusArgs {
  std::string dir;
  bool json = false;
};
int run_batch_status(const BatchStatusArgs& a);
struct BatchCollectArgs {
  std::string dir, out, csv;
};  // out: DATASET.h5, csv: the runs table; at least one
int run_batch_collect(const BatchCollectArgs& a);

}  // namespace dmgplace::cli
