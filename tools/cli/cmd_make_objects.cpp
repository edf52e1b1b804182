#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "dmgplace/tools/geometry/procedural_meshes.hpp"

namespace dmgplace::cli {

int run_make_objects(const MakeObjectsArgs& a) {
  std::filesystem::create_directories(a.out_dir);
  const std::filesystem::path dir(a.out_dir);
  tools::write_stl_binary(tools::make_eraser_mesh(), dir / "eraser.stl");
  tools::write_stl_binary(tools::make_bottle_mesh(), dir / "bottle.stl");
  std::cout << "wrote " << (dir / "eraser.stl").string() << " and " << (dir / "bottle.stl").string() << "\n";
  return 0;
}

}  // namespace dmgplace::cli
