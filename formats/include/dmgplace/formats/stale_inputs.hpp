#pragma once
// Is an artifact older than its inputs? Its header records each input's path (as given to the
// bake) and SHA-256. An input found again (as recorded, or beside the artifact) whose bytes hash
// differently means the artifact no longer describes it: bake again.
#include <filesystem>
#include <string>
#include <vector>

namespace dmgplace::formats {

struct InputStatus {
  std::string path;          // as recorded
  std::filesystem::path at;  // where it was found (empty: not found, cannot tell)
  bool changed = false;
};

// One entry per recorded input. Throws dmgplace::Error when the artifact cannot be read.
std::vector<InputStatus> check_inputs(const std::filesystem::path& artifact);

}  // namespace dmgplace::formats
