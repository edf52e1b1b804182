#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "dmgplace/formats/artifact_kind.hpp"

namespace dmgplace::cli {

int run_inspect(const InspectArgs& a) {
  auto summary = formats::inspect_artifact(a.file);
  if (!a.json) {
    for (const auto& [k, v] : summary) std::cout << k << ": " << v << "\n";
    return 0;
  }
  nlohmann::ordered_json j;
  for (const auto& [k, v] : summary) {
    if (k == "input") j["inputs"].push_back(v);
    else if (k == "parameters") j[k] = nlohmann::json::parse(v, nullptr, false);
    else j[k] = v;
  }
  std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace dmgplace::cli
