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
  // Typed: counts and sizes as numbers, bounds as arrays, the rest as text.
  const auto typed = [](const std::string& v) {
    auto parsed = nlohmann::ordered_json::parse(v, nullptr, false);
    return parsed.is_number() || parsed.is_array() ? parsed : nlohmann::ordered_json(v);
  };
  nlohmann::ordered_json j;
  j["inputs"] = nlohmann::ordered_json::array();
  for (const auto& [k, v] : summary) {
    if (k == "input") {
      const auto sep = v.find("  ");
      j["inputs"].push_back({{"sha256", v.substr(0, sep)}, {"path", sep == std::string::npos ? "" : v.substr(sep + 2)}});
    } else if (k == "parameters") {
      j[k] = nlohmann::ordered_json::parse(v, nullptr, false);
    } else {
      j[k] = typed(v);
    }
  }
  std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace dmgplace::cli
