#pragma once
// `dmgplace view`: a place result plus its artifacts -> one self-contained HTML page.
#include <cstddef>
#include <filesystem>

namespace dmgplace::tools::viewer {

struct ViewerSummary {
  bool solved = false;
  int steps = 0;          // path + retreat waypoints
  int frames = 0;         // animation frames after densifying
  std::size_t bytes = 0;  // page size
};

// Reads RESULT_DIR/result.json and the artifacts it names (looked up in `artifacts` when given),
// writes `html` atomically. Throws dmgplace::Error naming the offending file.
ViewerSummary write_viewer(const std::filesystem::path& result_dir, const std::filesystem::path& html,
                           const std::filesystem::path& artifacts = {});

}  // namespace dmgplace::tools::viewer
