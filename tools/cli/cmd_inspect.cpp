#include <iostream>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "commands.hpp"
#include "dmgplace/formats/artifact_kind.hpp"

namespace dmgplace::cli {

int run_inspect(const InspectArgs& a) {
  auto summary = formats::inspect_artifact(a.file);
  if (!a.json) {
    for (const auto& [k, v] : summary) std::cout << k << ": " << v << "\n";
    return 0;
  }
  const nlohmann::ordered_json j = artifact_json(a.file);
  std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace dmgplace::cli
