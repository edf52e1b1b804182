#include "dmgplace/formats/stale_inputs.hpp"

#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/sha256.hpp"

namespace dmgplace::formats {

std::vector<InputStatus> check_inputs(const std::filesystem::path& artifact) {
  const H5Reader reader(artifact);
  std::vector<InputStatus> out;
  for (const auto& input : reader.header().inputs) {
    InputStatus s;
    s.path = input.path;
    const std::filesystem::path recorded = input.path;
    // Relative paths were given from the bake's working directory, unknown here: try this one,
    // then the artifact's folder.
    for (const auto& candidate : {recorded, artifact.parent_path() / recorded}) {
      std::error_code ec;
      if (input.path.empty() || !std::filesystem::is_regular_file(candidate, ec)) continue;
      s.at = candidate;
      s.changed = sha256_file(candidate) != input.sha256;
      break;
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace dmgplace::formats
