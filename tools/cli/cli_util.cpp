#include "cli_util.hpp"

#include <iostream>

#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/sha256.hpp"

namespace dmgplace::cli {

formats::ArtifactHeader make_header(const nlohmann::json& parameters, const std::vector<std::filesystem::path>& inputs) {
  formats::ArtifactHeader h;
  h.tool_version = formats::tool_version();
  h.created_utc = formats::utc_now_iso8601();
  h.parameters_json = parameters.dump();
  for (const auto& p : inputs) h.inputs.push_back({p.string(), formats::sha256_file(p)});
  return h;
}

void report_written(const std::filesystem::path& path) {
  std::cout << "wrote " << path.string();
  auto summary = formats::inspect_artifact(path);
  const char* sep = " (";
  for (const auto& [k, v] : summary) {
    if (k == "file" || k == "parameters" || k == "input" || k == "created_utc" || k == "tool_version") continue;
    std::cout << sep << k << "=" << v;
    sep = ", ";
  }
  std::cout << ")\n";
}

}  // namespace dmgplace::cli
