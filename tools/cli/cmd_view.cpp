#include <iostream>

#include "commands.hpp"
#include "dmgplace/tools/viewer/write_viewer.hpp"

namespace dmgplace::cli {

int run_view(const ViewArgs& a) {
  const auto s = tools::viewer::write_viewer(a.result_dir, a.html, a.artifacts);
  std::cout << "wrote " << a.html << " (" << s.bytes / 1024 << " KiB): "
            << (s.solved ? std::to_string(s.steps) + " waypoints, " + std::to_string(s.frames) + " frames"
                         : std::string("no solution; scene and reason only"))
            << "\n";
  return 0;
}

}  // namespace dmgplace::cli
