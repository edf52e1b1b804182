#pragma once
// MANIFEST.yaml of `dmgplace batch`: named robots, objects and environments to bake, and query
// templates (objects x environments x initial grasps x variants x seeds) to run on them. Paths are
// relative to the manifest's folder; an object may be a glob (`ycb/*/textured.obj`), which
// becomes one object per match, named after the match's folder.
//
//   name: demo
//   robots:
//     dmgarm: {urdf: ../robots/dmgarm/dmgarm.urdf, srdf: ../robots/dmgarm/dmgarm.srdf, arm: dmgarm_link0:dmgarm_tcp}
//     panda: {urdf: ..., arm: ..., package_path: panda, flags: [--tcp, "0,0,0.1034,0,0,0,1"]}
//   (identities hash the URDF, SRDF, mesh and scene files named here, not the meshes a URDF
//   references through package_path)
//   objects:
//     bottle: {mesh: bottle.stl, flags: [--mass, "0.15"]}      # flags: bake-object's own
//     ycb: {glob: "ycb/*/textured.obj"}
//   environments:
//     cabinet: {scene: ../scenes/cabinet.yaml, volume: [0.55, -0.45, 0.4, 0.95, 0.45, 1.3], flags: [--margin, "0.9"]}
//   queries:
//     - name: cabinet
//       robot: dmgarm
//       objects: [bottle]
//       environments: [cabinet]
//       initial_grasps: {side: [0, 0, 0.06, 0, 0.7071068, 0, 0.7071068]}   # TCP in the object frame
//       start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]
//       variants: [full, no-regrasp]
//       seeds: 3
//       time_limit: 2
//       iterations: 0            # > 0: also stop after this many rounds (reproducible)
//       query: {volume: [...], objective: [...], options: {...}}   # copied into each query file
//     - name: chosen                # or an explicit list instead of the cross product:
//       robot: dmgarm
//       initial_grasps: {side: [...]}
//       start: [...]
//       runs: [{object: bottle, environment: cabinet, grasp: side, variant: full, seed: 7}]
#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace dmgplace::tools {

// One thing to bake: `dmgplace <command> <args...>`; `inputs` are the files its identity hashes.
struct BatchBake {
  std::string kind;  // robot, object, environment
  std::string name;
  std::vector<std::string> args;              // after the command, without --out
  std::vector<std::filesystem::path> inputs;  // files read (their bytes enter the identity)
};

// One query run of a template.
struct BatchRun {
  std::string object, environment, grasp, variant;
  int seed = 1;
};

struct BatchQueryTemplate {
  std::string name, robot;
  // The runs: objects x environments x initial grasps x variants x seeds, or the template's
  // explicit `runs:` list ({object, environment, grasp, variant, seed} each).
  std::vector<BatchRun> runs;
  std::vector<std::string> objects, environments;
  std::vector<std::pair<std::string, std::array<double, 7>>> grasps;  // name -> TCP pose in the object frame
  std::vector<double> start;
  std::vector<std::string> variants{"full"};
  int seeds = 1;
  double time_limit = 2;
  long iterations = 0;
  std::string extra_yaml;  // the template's `query:` map, emitted as YAML
};

struct BatchManifest {
  std::filesystem::path path;
  std::string name;
  std::vector<BatchBake> bakes;  // robots, then objects, then environments, each sorted by name
  std::vector<BatchQueryTemplate> queries;
};

// Reads and checks a manifest: unknown or duplicate keys, missing files, names that are not file
// names, references to undefined robots/objects/environments are dmgplace::Error naming the element.
BatchManifest read_batch_manifest(const std::filesystem::path& path);

}  // namespace dmgplace::tools
