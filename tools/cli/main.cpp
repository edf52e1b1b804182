// The dmgplace command line: the only file that sees CLI11.
#include <CLI/CLI.hpp>

#include <cmath>
#include <iostream>
#include <sstream>
#include <type_traits>
#include <variant>

#include "cli_log.hpp"
#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/error.hpp"

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

}  // namespace

int main(int argc, char** argv) {
  using namespace dmgplace::cli;
  CLI::App app{"dmgplace: placement planning with in-hand regrasping (Dexterous Manipulation Graphs)"};
  app.set_version_flag("--version", dmgplace::formats::tool_version());
  app.require_subcommand(1);
  // Messages on stderr for every command (results stay on stdout): cli_log.hpp.
  std::string log_level = "info";
  bool verbose = false, quiet = false;
  app.add_option("--log-level", log_level, "Messages on stderr: trace, debug, info, warning, error, off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warning", "warn", "error", "off"}))
      ->capture_default_str();
  app.add_flag("-v,--verbose", verbose, "Debug messages too (--log-level debug)");
  app.add_flag("-q,--quiet", quiet, "Warnings and errors only (--log-level warning)");
  app.fallthrough();
  app.footer(
      "Exit codes: 0 done; 1 bad input or failure (the message names the file, element and reason); "
      "3 no solution (place, plan); 103-114 a malformed command line (CLI11).");

  ValidateArgs validate;
  auto* c_validate =
      app.add_subcommand("validate", "Check artifacts: schema, checksums, invariants; one line per problem");
  c_validate->add_option("files", validate.files, "Artifact files (.h5)")->required();
  c_validate->add_flag("--quiet,-q", validate.quiet, "Print only problems");
  c_validate->add_flag("--json", validate.json, "Print JSON: per file ok and its problems; totals");
  c_validate->add_flag("--set", validate.set,
                       "The files are one robot, one object and one environment: also check they fit together (gripper "
                       "opening, reach, units)");
  c_validate->add_flag("--check-inputs", validate.check_inputs,
                       "Also report inputs that changed since the bake (where they still exist)");
  c_validate->add_flag("--deep", validate.deep,
                       "Also hold each artifact's numbers against its own exact geometry (fields, sphere cover, "
                       "self-distance tables, mass); with --check-inputs, joint limits against the URDF");
  c_validate->add_option("--samples", validate.samples, "--deep: samples per check")->check(CLI::Range(1, 10'000'000));
  c_validate->add_option("--seed", validate.seed, "--deep: random seed of the samples");

  InspectArgs inspect;
  auto* c_inspect = app.add_subcommand("inspect", "Summarise an artifact (counts, bounds, parameters)");
  c_inspect->add_option("file", inspect.file, "Artifact file")->required();
  c_inspect->add_flag("--json", inspect.json, "Print JSON");

  BakeObjectArgs bake_object;
  auto* c_obj = app.add_subcommand("bake-object", "Analyse a rigid object mesh once into OBJECT.h5");
  c_obj
      ->add_option("inputs", bake_object.inputs,
                   "One mesh (STL, OBJ, PLY, DAE), or PCD scans of the object (each with its sensor VIEWPOINT)")
      ->required();
  bind_options(c_obj, bake_object.options());
  c_obj->get_option("--out")->required();
  c_obj->add_option("--com", bake_object.com_text,
                    "Center of mass x,y,z (m, mesh frame; object frame for scans), overrides the computed one");
  c_obj->add_option("--crop", bake_object.crop_text,
                    "Scans: keep points in the box xmin,ymin,zmin,xmax,ymax,zmax (m, scan frame)");
  c_obj->add_option("--cluster-near", bake_object.near_text, "Scans: take the cluster nearest x,y,z (m, scan frame)");

  PlaceArgs place;
  auto* c_place =
      app.add_subcommand("place", "Plan a placement (anytime): in-hand regrasp, arm path, best pose so far");
  c_place->add_option("query", place.query, "Query YAML (artifacts, start, initial grasp, volume, objective)")
      ->required();
  c_place->add_option("--artifacts", place.artifacts,
                      "Folder the query's relative artifact paths are in (default: the query's folder)");
  c_place->add_option("--out", place.out, "Output folder for result.json, trace.csv, path.csv");
  c_place->add_option("--time-limit", place.time_limit, "Seconds (overrides the query's)")->check(CLI::Range(0.0, 1e6));
  c_place->add_option("--seed", place.seed, "Random seed (overrides the query's)");
  c_place->add_option("--threads", place.threads, "Motion planner threads; 0: synchronous, deterministic")
      ->check(CLI::Range(0, 256));
  c_place->add_flag("--allow-outside", place.allow_outside, "Let the query's artifact paths leave the artifact folder");
  c_place
      ->add_option(
          "--iterations", place.iterations,
          "Also stop after this many search rounds (0: no limit): with --threads 0, the same result on every machine")
      ->check(CLI::Range(0L, 1000000000L));
  c_place->add_option("--variant", place.variant, "full, random-grasp or no-regrasp (overrides the query's)");
  c_place->add_option("--pusher", place.pusher,
                      "none: leave the query's pusher arm out (the in-hand actions are not planned for it)");
  c_place->add_flag("--json", place.json, "Also print result.json to stdout");
  c_place
      ->add_option("--trajectory-format", place.trajectory_format,
                   "json: trajectory.json; moveit: also trajectory_approach.yaml and trajectory_retreat.yaml "
                   "(trajectory_msgs/JointTrajectory)")
      ->check(CLI::IsMember({"json", "moveit"}));

  ExperimentArgs experiment;
  auto* c_exp = app.add_subcommand("experiment", "Run a grid of placement problems x variants x seeds (resumable)");
  c_exp->add_option("spec", experiment.spec, "Experiment SPEC.yaml")->required();
  c_exp->add_option("--out", experiment.out, "Output folder (runs/, summary.csv)")->required();
  c_exp->add_option("--artifacts", experiment.artifacts, "Folder of the queries' artifacts (overrides the spec's)");
  c_exp->add_option("--runs", experiment.runs, "Seeds per problem and variant (overrides the spec's)")
      ->check(CLI::Range(1, 100000));
  c_exp->add_option("--jobs", experiment.jobs, "Runs at a time")->check(CLI::Range(1, 256));
  c_exp->add_option("--time-limit", experiment.time_limit, "Seconds per run (overrides the spec's)")
      ->check(CLI::Range(0.0, 1e6));
  c_exp->add_flag("--quick", experiment.quick, "The spec's quick preset: a few seeds, seconds per run");

  PlotArgs plot;
  auto* c_plot = app.add_subcommand("plot", "Objective and success against time for an experiment folder (SVG, PNG)");
  c_plot->add_option("dir", plot.dir, "Experiment output folder")->required();

  ViewArgs view;
  auto* c_view = app.add_subcommand("view", "Write a self-contained 3-D viewer page (HTML) for a placement result");
  c_view->add_option("result_dir", view.result_dir, "Output folder of `dmgplace place` (result.json)")->required();
  c_view->add_option("--html", view.html, "HTML file to write")->required();
  c_view->add_option("--artifacts", view.artifacts, "Folder of the artifacts, when moved since the run");

  GraspsArgs grasps;
  std::string initial_text;
  auto* c_grasps = app.add_subcommand("grasps", "Grasps reachable in-hand from an initial grasp (DMG + Dijkstra)");
  c_grasps->add_option("object", grasps.object, "Object artifact (OBJECT.h5)")->required();
  c_grasps->add_option("--initial", initial_text, "Initial TCP pose in the object frame: x,y,z,qx,qy,qz,qw")
      ->required();
  c_grasps->add_option("--opening", grasps.opening, "Initial finger opening (m)")->check(CLI::Range(0.0, 1.0));
  c_grasps->add_flag("--json", grasps.json, "Print JSON");

  BakeEnvArgs bake_env;
  auto* c_env = app.add_subcommand("bake-env", "Analyse an environment once into ENV.h5");
  c_env->add_option("scene", bake_env.scene, "Scene: URDF of fixed links, PlanningScene YAML, mesh or PCD scan")
      ->required();
  c_env->add_option("--volume", bake_env.volume_text, "Target volume xmin,ymin,zmin,xmax,ymax,zmax (metres)")
      ->required();
  c_env->add_option("--frame", bake_env.frame_text,
                    "Pose of the scene file in the world (robot base) frame: x,y,z,roll,pitch,yaw; a scan's camera "
                    "pose, a scene's offset");
  bind_options(c_env, bake_env.options());
  c_env->get_option("--out")->required();

  BakeRobotArgs bake_robot;
  auto* c_robot = app.add_subcommand("bake-robot", "Analyse a robot (URDF + SRDF) once into ROBOT.h5");
  c_robot->add_option("urdf", bake_robot.urdf, "Robot URDF")->required();
  c_robot->add_option("--tcp", bake_robot.tcp_text,
                      "Tool center point on the tip link x,y,z,qx,qy,qz,qw; becomes the chain's tip (<tip>_tcp)");
  bind_options(c_robot, bake_robot.options());
  c_robot->get_option("--out")->required();
  c_robot->get_option("--arm")->required();

  PlanArgs plan;
  auto* c_plan = app.add_subcommand("plan", "Plan one MoveIt/MotionBenchMaker problem (scene + joint-space request)");
  c_plan->add_option("scene", plan.scene, "PlanningScene YAML")->required();
  c_plan->add_option("request", plan.request, "MotionPlanRequest YAML with a joint-space goal")->required();
  c_plan->add_option("--robot", plan.robot, "Robot artifact from bake-robot")->required();
  c_plan->add_option("--time-limit", plan.time_limit, "Seconds")->check(CLI::Range(1e-3, 1e6));
  c_plan->add_option("--resolution", plan.resolution, "Motion check step in radians")->check(CLI::Range(1e-4, 1.0));
  c_plan->add_option("--sdf-resolution", plan.sdf_resolution, "Workspace distance grid cell (m)")
      ->check(CLI::Range(1e-3, 1.0));
  c_plan->add_option("--seed", plan.seed, "Random seed");
  c_plan->add_option("--out", plan.out, "Write the path and its timed trajectory as JSON");
  c_plan
      ->add_option("--velocity-scaling", plan.velocity_scaling,
                   "Fraction of the joints' velocity limits for the trajectory")
      ->check(CLI::Range(1e-6, 1.0));
  c_plan->add_option("--acceleration-scaling", plan.acceleration_scaling, "Fraction of the joints' acceleration limits")
      ->check(CLI::Range(1e-6, 1.0));
  c_plan
      ->add_option("--trajectory-format", plan.trajectory_format,
                   "moveit: also write OUT's stem + .trajectory.yaml (trajectory_msgs/JointTrajectory)")
      ->check(CLI::IsMember({"json", "moveit"}));

  BenchMbmArgs bench_mbm;
  auto* c_bench =
      app.add_subcommand("bench-mbm", "Run MotionBenchMaker problem folders with ours and stock OMPL RRTConnect+FCL");
  c_bench->add_option("dirs", bench_mbm.dirs, "Problem folders (sceneNNNN.yaml + requestNNNN.yaml)")->required();
  c_bench->add_option("--robot", bench_mbm.robot, "Robot artifact from bake-robot")->required();
  c_bench->add_option("--runs", bench_mbm.runs, "Runs per problem and planner")->check(CLI::Range(1, 10000));
  c_bench->add_option("--limit", bench_mbm.limit, "Use only the first N problems of each folder")
      ->check(CLI::Range(0, 1000000));
  c_bench->add_option("--time-limit", bench_mbm.time_limit, "Seconds per run")->check(CLI::Range(1e-3, 1e6));
  c_bench->add_option("--sdf-resolution", bench_mbm.sdf_resolution, "Workspace distance grid cell (m) for ours")
      ->check(CLI::Range(1e-3, 1.0));
  c_bench->add_option("--resolution", bench_mbm.resolution, "Motion check step in radians")
      ->check(CLI::Range(1e-4, 1.0));
  c_bench->add_option("--csv", bench_mbm.csv, "Write every run as CSV");
  c_bench->add_option("--planners", bench_mbm.planners, "Which planners to run (the ratio needs both)")
      ->check(CLI::IsMember({"ours", "stock", "both"}));
  c_bench
      ->add_option("--field", bench_mbm.field,
                   "Ours: auto (no distance field for a scene of at most 64 primitives) or always")
      ->check(CLI::IsMember({"auto", "always"}));
  c_bench
      ->add_option("--stock-bvh", bench_mbm.stock_bvh,
                   "FCL mesh BVHs of the stock baseline: obbrss (as MoveIt builds them) or obb (as our exact layer)")
      ->check(CLI::IsMember({"obbrss", "obb"}));

  BatchArgs batch;
  auto* c_batch =
      app.add_subcommand("batch", "Bake and query a manifest's grid: content-addressed, resumable, sharded, Slurm");
  c_batch->add_option("manifest", batch.manifest, "MANIFEST.yaml (robots, objects, environments, query templates)")
      ->required();
  c_batch->add_option("--out", batch.out, "Batch folder (artifacts/, runs/, state/, batch.json)")->required();
  c_batch->add_option("--jobs", batch.jobs, "Tasks at a time")->check(CLI::Range(1, 256));
  c_batch->add_option("--shard", batch.shard, "Run shard I of N (I/N): N shards partition the tasks");
  c_batch->add_option("--phase", batch.phase, "all, bakes or queries")
      ->check(CLI::IsMember({"all", "bakes", "queries"}));
  c_batch->add_flag("--keep-going", batch.keep_going, "Record failures and go on (the default)");
  c_batch->add_flag("--dry-run", batch.dry_run, "List the tasks that would run (with --slurm: write the scripts only)");
  c_batch->add_flag("--json", batch.json, "One JSON object per finished task on stdout");
  c_batch->add_flag("--no-deep", batch.no_deep, "Do not run `validate --deep` on each bake's output");
  c_batch->add_flag("--slurm", batch.slurm, "Write and submit two sbatch array jobs (bakes, then queries afterok)");
  c_batch->add_option("--partition", batch.partition, "Slurm partition");
  c_batch->add_option("--array-size", batch.array_size, "Slurm array tasks (shards)")->check(CLI::Range(1, 100000));
  c_batch->add_option("--time", batch.time, "Slurm time limit per array task, HH:MM:SS");
  BatchStatusArgs batch_status;
  auto* c_bstatus =
      app.add_subcommand("batch-status", "Done / failed (with the error) / pending tasks of a batch folder");
  c_bstatus->add_option("dir", batch_status.dir, "Batch folder")->required();
  c_bstatus->add_flag("--json", batch_status.json, "Print JSON");
  BatchCollectArgs batch_collect;
  auto* c_bcollect =
      app.add_subcommand("batch-collect", "One dataset file (HDF5 tables: runs, paths, in-hand actions, traces)");
  c_bcollect->add_option("dir", batch_collect.dir, "Batch folder")->required()->check(CLI::ExistingDirectory);
  const CLI::Validator file_name(
      [](std::string& s) { return s.empty() ? std::string("an empty file name") : std::string(); }, "FILE");
  c_bcollect->add_option("--out", batch_collect.out, "DATASET.h5 (docs/batch.md has its layout)")->check(file_name);
  c_bcollect->add_option("--csv", batch_collect.csv, "Also (or only) the runs table as CSV, one row per run")
      ->check(file_name);

  MakeObjectsArgs make_objects;
  auto* c_make = app.add_subcommand("make-objects", "Write the built-in procedural object meshes (eraser, bottle)");
  c_make->add_option("--out", make_objects.out_dir, "Output folder")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  init_logging(quiet ? "warning" : verbose ? "debug" : log_level);

  try {
    if (*c_validate) return run_validate(validate);
    if (*c_inspect) return run_inspect(inspect);
    if (*c_obj) return run_bake_object(bake_object);
    if (*c_place) return run_place(place);
    if (*c_exp) return run_experiment(experiment);
    if (*c_plot) return run_plot(plot);
    if (*c_view) return run_view(view);
    if (*c_grasps) {
      grasps.initial = parse_numbers<7>(initial_text, "--initial");
      return run_grasps(grasps);
    }
    if (*c_env) return run_bake_env(bake_env);
    if (*c_robot) return run_bake_robot(bake_robot);
    if (*c_make) return run_make_objects(make_objects);
    if (*c_batch) return run_batch(batch);
    if (*c_bstatus) return run_batch_status(batch_status);
    if (*c_bcollect) return run_batch_collect(batch_collect);
    if (*c_plan) return run_plan(plan);
    if (*c_bench) return run_bench_mbm(bench_mbm);
  } catch (const dmgplace::Error& e) {
    log_error(e.what());
    return 1;
  } catch (const std::exception& e) {
    log_error(std::string("unexpected failure: ") + e.what());
    return 1;
  }
  return 0;
}
