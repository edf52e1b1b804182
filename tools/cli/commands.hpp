#pragma once
// One plain function per subcommand; the command line itself (CLI11) lives only in main.cpp.
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace dmgplace::cli {

struct ValidateArgs { std::vector<std::string> files; bool quiet = false; };
int run_validate(const ValidateArgs& a);

struct InspectArgs { std::string file; bool json = false; };
int run_inspect(const InspectArgs& a);

struct BakeObjectArgs {
  std::string mesh, out;
  double scale = 1.0;
  std::optional<std::array<double, 3>> com;
  double mass = 0;  // <= 0: from volume at 1000 kg/m^3
};
int run_bake_object(const BakeObjectArgs& a);

struct BakeEnvArgs {
  std::string scene, out;
  std::array<double, 6> volume{};
  std::optional<std::array<double, 6>> frame;  // x y z roll pitch yaw for scans
  std::vector<std::string> package_paths;
};
int run_bake_env(const BakeEnvArgs& a);

struct BakeRobotArgs {
  std::string urdf, srdf, arm, out;
  double sphere_max_radius = 0.08;  // metres
  double sphere_spacing = 0.005;    // metres between coverage samples
  std::vector<std::string> package_paths;
};
int run_bake_robot(const BakeRobotArgs& a);

struct MakeObjectsArgs { std::string out_dir; };
int run_make_objects(const MakeObjectsArgs& a);

}  // namespace dmgplace::cli
