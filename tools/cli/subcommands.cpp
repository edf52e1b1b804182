#include "subcommands.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <type_traits>
#include <variant>

#include "cli_util.hpp"
#include "commands.hpp"

namespace dmgplace::cli {
namespace {

// Binds an option table (option_table.hpp): numbers with their range checked at parse time, help
// with unit and default, text options limited to their choices, flags.
void bind_options(CLI::App* app, const dmgplace::cli::OptionTable& table) {
  for (const auto& row : table) {
    const std::string help = row.unit.empty() ? row.help : row.help + " (" + row.unit + ")";
    std::visit(
        [&](auto* v) {
          using T = std::remove_pointer_t<decltype(v)>;
          if constexpr (std::is_same_v<T, bool>) {
            app->add_flag(row.flag, *v, help);
          } else {
            auto* o = app->add_option(row.flag, *v, help)->capture_default_str();
            if constexpr (std::is_arithmetic_v<T>) o->check(CLI::Range(T(row.lo), T(row.hi)));
            else if (!row.choices.empty()) o->check(CLI::IsMember(row.choices));
          }
        },
        row.value);
  }
}

// A subcommand whose arguments live as long as its runner.
template <class Args, class Define, class Run>
Subcommand add(CLI::App& app, const char* name, const char* help, Define define, Run run) {
  auto args = std::make_shared<Args>();
  CLI::App* c = app.add_subcommand(name, help);
  define(*c, *args);
  return {c, [args, run] { return run(*args); }};
}

void define_validate(CLI::App& c, ValidateArgs& a) {
  c.add_option("files", a.files, "Artifact files (.h5)")->required();
  c.add_flag("--quiet,-q", a.quiet, "Print only problems");
  c.add_flag("--json", a.json, "Print JSON: per file ok and its problems; totals");
  c.add_flag("--set", a.set,
             "The files are one robot, one object and one environment: also check they fit together (gripper "
             "opening, reach, units)");
  c.add_flag("--check-inputs", a.check_inputs,
             "Also report inputs that changed since the bake (where they still exist)");
  c.add_flag("--deep", a.deep,
             "Also hold each artifact's numbers against its own exact geometry (fields, sphere cover, "
             "self-distance tables, mass); with --check-inputs, joint limits against the URDF");
  c.add_option("--samples", a.samples, "--deep: samples per check")->check(CLI::Range(1, 10'000'000));
  c.add_option("--seed", a.seed, "--deep: random seed of the samples");
}

void define_inspect(CLI::App& c, InspectArgs& a) {
  c.add_option("file", a.file, "Artifact file")->required();
  c.add_flag("--json", a.json, "Print JSON");
}

void define_bake_object(CLI::App& c, BakeObjectArgs& a) {
  c.add_option("inputs", a.inputs,
               "One mesh (STL, OBJ, PLY, DAE), or PCD scans of the object (each with its sensor VIEWPOINT)")
      ->required();
  bind_options(&c, a.options());
  c.get_option("--out")->required();
  c.add_option("--com", a.com_text,
               "Center of mass x,y,z (m, mesh frame; object frame for scans), overrides the computed one");
  c.add_option("--crop", a.crop_text, "Scans: keep points in the box xmin,ymin,zmin,xmax,ymax,zmax (m, scan frame)");
  c.add_option("--cluster-near", a.near_text, "Scans: take the cluster nearest x,y,z (m, scan frame)");
}

void define_place(CLI::App& c, PlaceArgs& a) {
  c.add_option("query", a.query, "Query YAML (artifacts, start, initial grasp, volume, objective)")->required();
  c.add_option("--artifacts", a.artifacts,
               "Folder the query's relative artifact paths are in (default: the query's folder)");
  c.add_option("--out", a.out, "Output folder for result.json, trace.csv, path.csv");
  c.add_option("--time-limit", a.time_limit, "Seconds (overrides the query's)")->check(CLI::Range(0.0, 1e6));
  c.add_option("--seed", a.seed, "Random seed (overrides the query's)");
  c.add_option("--threads", a.threads, "Motion planner threads; 0: synchronous, deterministic")
      ->check(CLI::Range(0, 256));
  c.add_flag("--allow-outside", a.allow_outside, "Let the query's artifact paths leave the artifact folder");
  c.add_option(
       "--iterations", a.iterations,
       "Also stop after this many search rounds (0: no limit): with --threads 0, the same result on every machine")
      ->check(CLI::Range(0L, 1000000000L));
  c.add_option("--variant", a.variant, "full, random-grasp or no-regrasp (overrides the query's)");
  c.add_option("--pusher", a.pusher,
               "none: leave the query's pusher arm out (the in-hand actions are not planned for it)");
  c.add_flag("--json", a.json, "Also print result.json to stdout");
  c.add_option("--trajectory-format", a.trajectory_format,
               "json: trajectory.json; moveit: also trajectory_approach.yaml and trajectory_retreat.yaml "
               "(trajectory_msgs/JointTrajectory)")
      ->check(CLI::IsMember({"json", "moveit"}));
}

void define_experiment(CLI::App& c, ExperimentArgs& a) {
  c.add_option("spec", a.spec, "Experiment SPEC.yaml")->required();
  c.add_option("--out", a.out, "Output folder (runs/, summary.csv)")->required();
  c.add_option("--artifacts", a.artifacts, "Folder of the queries' artifacts (overrides the spec's)");
  c.add_option("--runs", a.runs, "Seeds per problem and variant (overrides the spec's)")->check(CLI::Range(1, 100000));
  c.add_option("--jobs", a.jobs, "Runs at a time")->check(CLI::Range(1, 256));
  c.add_option("--time-limit", a.time_limit, "Seconds per run (overrides the spec's)")->check(CLI::Range(0.0, 1e6));
  c.add_flag("--quick", a.quick, "The spec's quick preset: a few seeds, seconds per run");
}

void define_plot(CLI::App& c, PlotArgs& a) { c.add_option("dir", a.dir, "Experiment output folder")->required(); }

void define_view(CLI::App& c, ViewArgs& a) {
  c.add_option("result_dir", a.result_dir, "Output folder of `dmgplace place` (result.json)")->required();
  c.add_option("--html", a.html, "HTML file to write")->required();
  c.add_option("--artifacts", a.artifacts, "Folder of the artifacts, when moved since the run");
}

// The initial grasp is read as text and parsed after the command line (parse_numbers names the
// option in its error).
struct GraspsCommand {
  GraspsArgs args;
  std::string initial_text;
};
void define_grasps(CLI::App& c, GraspsCommand& g) {
  GraspsArgs& a = g.args;
  c.add_option("object", a.object, "Object artifact (OBJECT.h5)")->required();
  c.add_option("--initial", g.initial_text, "Initial TCP pose in the object frame: x,y,z,qx,qy,qz,qw")->required();
  c.add_option("--opening", a.opening, "Initial finger opening (m)")->check(CLI::Range(0.0, 1.0));
  c.add_flag("--json", a.json, "Print JSON");
}
int run_grasps_command(GraspsCommand& g) {
  g.args.initial = parse_numbers<7>(g.initial_text, "--initial");
  return run_grasps(g.args);
}

void define_bake_env(CLI::App& c, BakeEnvArgs& a) {
  c.add_option("scene", a.scene, "Scene: URDF of fixed links, PlanningScene YAML, mesh or PCD scan")->required();
  c.add_option("--volume", a.volume_text, "Target volume xmin,ymin,zmin,xmax,ymax,zmax (metres)")->required();
  c.add_option("--frame", a.frame_text,
               "Pose of the scene file in the world (robot base) frame: x,y,z,roll,pitch,yaw; a scan's camera "
               "pose, a scene's offset");
  bind_options(&c, a.options());
  c.get_option("--out")->required();
}

void define_bake_robot(CLI::App& c, BakeRobotArgs& a) {
  c.add_option("urdf", a.urdf, "Robot URDF")->required();
  c.add_option("--tcp", a.tcp_text,
               "Tool center point on the tip link x,y,z,qx,qy,qz,qw; becomes the chain's tip (<tip>_tcp)");
  bind_options(&c, a.options());
  c.get_option("--out")->required();
  c.get_option("--arm")->required();
}

void define_plan(CLI::App& c, PlanArgs& a) {
  c.add_option("scene", a.scene, "PlanningScene YAML")->required();
  c.add_option("request", a.request, "MotionPlanRequest YAML with a joint-space goal")->required();
  c.add_option("--robot", a.robot, "Robot artifact from bake-robot")->required();
  c.add_option("--time-limit", a.time_limit, "Seconds")->check(CLI::Range(1e-3, 1e6));
  c.add_option("--resolution", a.resolution, "Motion check step in radians")->check(CLI::Range(1e-4, 1.0));
  c.add_option("--sdf-resolution", a.sdf_resolution, "Workspace distance grid cell (m)")->check(CLI::Range(1e-3, 1.0));
  c.add_option("--seed", a.seed, "Random seed");
  c.add_option("--out", a.out, "Write the path and its timed trajectory as JSON");
  c.add_option("--velocity-scaling", a.velocity_scaling, "Fraction of the joints' velocity limits for the trajectory")
      ->check(CLI::Range(1e-6, 1.0));
  c.add_option("--acceleration-scaling", a.acceleration_scaling, "Fraction of the joints' acceleration limits")
      ->check(CLI::Range(1e-6, 1.0));
  c.add_option("--trajectory-format", a.trajectory_format,
               "moveit: also write OUT's stem + .trajectory.yaml (trajectory_msgs/JointTrajectory)")
      ->check(CLI::IsMember({"json", "moveit"}));
}

void define_bench_mbm(CLI::App& c, BenchMbmArgs& a) {
  c.add_option("dirs", a.dirs, "Problem folders (sceneNNNN.yaml + requestNNNN.yaml)")->required();
  c.add_option("--robot", a.robot, "Robot artifact from bake-robot")->required();
  c.add_option("--runs", a.runs, "Runs per problem and planner")->check(CLI::Range(1, 10000));
  c.add_option("--limit", a.limit, "Use only the first N problems of each folder")->check(CLI::Range(0, 1000000));
  c.add_option("--time-limit", a.time_limit, "Seconds per run")->check(CLI::Range(1e-3, 1e6));
  c.add_option("--sdf-resolution", a.sdf_resolution, "Workspace distance grid cell (m) for ours")
      ->check(CLI::Range(1e-3, 1.0));
  c.add_option("--resolution", a.resolution, "Motion check step in radians")->check(CLI::Range(1e-4, 1.0));
  c.add_option("--csv", a.csv, "Write every run as CSV");
  c.add_option("--planners", a.planners, "Which planners to run (the ratio needs both)")
      ->check(CLI::IsMember({"ours", "stock", "both"}));
  c.add_option("--field", a.field, "Ours: auto (no distance field for a scene of at most 64 primitives) or always")
      ->check(CLI::IsMember({"auto", "always"}));
  c.add_option("--stock-bvh", a.stock_bvh,
               "FCL mesh BVHs of the stock baseline: obbrss (as MoveIt builds them) or obb (as our exact layer)")
      ->check(CLI::IsMember({"obbrss", "obb"}));
}

void define_batch(CLI::App& c, BatchArgs& a) {
  c.add_option("manifest", a.manifest, "MANIFEST.yaml (robots, objects, environments, query templates)")->required();
  c.add_option("--out", a.out, "Batch folder (artifacts/, runs/, state/, batch.json)")->required();
  c.add_option("--jobs", a.jobs, "Tasks at a time")->check(CLI::Range(1, 256));
  c.add_option("--shard", a.shard, "Run shard I of N (I/N): N shards partition the tasks");
  c.add_option("--phase", a.phase, "all, bakes or queries")->check(CLI::IsMember({"all", "bakes", "queries"}));
  c.add_flag("--keep-going", a.keep_going, "Record failures and go on (the default)");
  c.add_flag("--dry-run", a.dry_run, "List the tasks that would run (with --slurm: write the scripts only)");
  c.add_flag("--json", a.json, "One JSON object per finished task on stdout");
  c.add_flag("--no-deep", a.no_deep, "Do not run `validate --deep` on each bake's output");
  c.add_flag("--slurm", a.slurm, "Write and submit two sbatch array jobs (bakes, then queries afterok)");
  c.add_option("--partition", a.partition, "Slurm partition");
  c.add_option("--array-size", a.array_size, "Slurm array tasks (shards)")->check(CLI::Range(1, 100000));
  c.add_option("--time", a.time, "Slurm time limit per array task, HH:MM:SS");
}

void define_batch_status(CLI::App& c, BatchStatusArgs& a) {
  c.add_option("dir", a.dir, "Batch folder")->required();
  c.add_flag("--json", a.json, "Print JSON");
}

void define_batch_collect(CLI::App& c, BatchCollectArgs& a) {
  c.add_option("dir", a.dir, "Batch folder")->required()->check(CLI::ExistingDirectory);
  const CLI::Validator file_name(
      [](std::string& s) { return s.empty() ? std::string("an empty file name") : std::string(); }, "FILE");
  c.add_option("--out", a.out, "DATASET.h5 (docs/batch.md has its layout)")->check(file_name);
  c.add_option("--csv", a.csv, "Also (or only) the runs table as CSV, one row per run")->check(file_name);
}

void define_make_objects(CLI::App& c, MakeObjectsArgs& a) {
  c.add_option("--out", a.out_dir, "Output folder")->required();
}

}  // namespace

std::vector<Subcommand> add_subcommands(CLI::App& app) {
  // A braced list is evaluated in order: the help lists the subcommands as here.
  return {
      add<ValidateArgs>(app, "validate", "Check artifacts: schema, checksums, invariants; one line per problem",
                        define_validate, run_validate),
      add<InspectArgs>(app, "inspect", "Summarise an artifact (counts, bounds, parameters)", define_inspect,
                       run_inspect),
      add<BakeObjectArgs>(app, "bake-object", "Analyse a rigid object mesh once into OBJECT.h5", define_bake_object,
                          run_bake_object),
      add<PlaceArgs>(app, "place", "Plan a placement (anytime): in-hand regrasp, arm path, best pose so far",
                     define_place, run_place),
      add<ExperimentArgs>(app, "experiment", "Run a grid of placement problems x variants x seeds (resumable)",
                          define_experiment, run_experiment),
      add<PlotArgs>(app, "plot", "Objective and success against time for an experiment folder (SVG, PNG)", define_plot,
                    run_plot),
      add<ViewArgs>(app, "view", "Write a self-contained 3-D viewer page (HTML) for a placement result", define_view,
                    run_view),
      add<GraspsCommand>(app, "grasps", "Grasps reachable in-hand from an initial grasp (DMG + Dijkstra)",
                         define_grasps, run_grasps_command),
      add<BakeEnvArgs>(app, "bake-env", "Analyse an environment once into ENV.h5", define_bake_env, run_bake_env),
      add<BakeRobotArgs>(app, "bake-robot", "Analyse a robot (URDF + SRDF) once into ROBOT.h5", define_bake_robot,
                         run_bake_robot),
      add<PlanArgs>(app, "plan", "Plan one MoveIt/MotionBenchMaker problem (scene + joint-space request)", define_plan,
                    run_plan),
      add<BenchMbmArgs>(app, "bench-mbm",
                        "Run MotionBenchMaker problem folders with ours and stock OMPL RRTConnect+FCL",
                        define_bench_mbm, run_bench_mbm),
      add<BatchArgs>(app, "batch", "Bake and query a manifest's grid: content-addressed, resumable, sharded, Slurm",
                     define_batch, run_batch),
      add<BatchStatusArgs>(app, "batch-status", "Done / failed (with the error) / pending tasks of a batch folder",
                           define_batch_status, run_batch_status),
      add<BatchCollectArgs>(app, "batch-collect",
                            "One dataset file (HDF5 tables: runs, paths, in-hand actions, traces)",
                            define_batch_collect, run_batch_collect),
      add<MakeObjectsArgs>(app, "make-objects", "Write the built-in procedural object meshes (eraser, bottle)",
                           define_make_objects, run_make_objects),
  };
}

}  // namespace dmgplace::cli
