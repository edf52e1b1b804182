#include "cli_util.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include "dmgplace/formats/error.hpp"

#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/sha256.hpp"

namespace dmgplace::cli {

formats::ArtifactHeader make_header(const nlohmann::json& parameters, const std::vector<std::filesystem::path>& inputs,
                                    const std::vector<std::filesystem::path>& read) {
  formats::ArtifactHeader h;
  h.tool_version = formats::tool_version();
  h.created_utc = formats::utc_now_iso8601();
  h.parameters_json = parameters.dump();
  for (const auto& p : inputs) h.inputs.push_back({p.string(), formats::sha256_file(p)});
  for (const auto& p : read) {
    const bool listed = std::any_of(h.inputs.begin(), h.inputs.end(),
                                    [&](const formats::InputFile& f) { return f.path == p.string(); });
    if (!listed) h.inputs.push_back({p.string(), formats::sha256_file(p)});
  }
  return h;
}

nlohmann::ordered_json artifact_json(const std::filesystem::path& path) {
  const auto typed = [](const std::string& v) {
    auto parsed = nlohmann::ordered_json::parse(v, nullptr, false);
    return parsed.is_number() || parsed.is_array() ? parsed : nlohmann::ordered_json(v);
  };
  nlohmann::ordered_json j;
  j["inputs"] = nlohmann::ordered_json::array();
  for (const auto& [k, v] : formats::inspect_artifact(path)) {
    if (k == "input") {
      const auto sep = v.find("  ");
      j["inputs"].push_back(
          {{"sha256", v.substr(0, sep)}, {"path", sep == std::string::npos ? "" : v.substr(sep + 2)}});
    } else if (k == "parameters") {
      j[k] = nlohmann::ordered_json::parse(v, nullptr, false);
    } else {
      j[k] = typed(v);
    }
  }
  return j;
}

void report_written(const std::filesystem::path& path, bool json, double seconds, const nlohmann::ordered_json& extra) {
  if (json) {
    nlohmann::ordered_json j{{"written", path.string()}, {"seconds", seconds}};
    for (const auto& [k, v] : extra.items()) j[k] = v;
    j["artifact"] = artifact_json(path);
    std::cout << j.dump(2) << "\n";
    return;
  }
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

std::vector<double> parse_numbers(const std::string& text, std::size_t n, const std::string& flag) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      const double v = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(v)) throw std::invalid_argument(item);
      out.push_back(v);
    } catch (const std::exception&) {
      throw Error(flag, "", "'" + item + "' is not a finite number");
    }
  }
  if (out.size() != n)
    throw Error(flag, "", "expected " + std::to_string(n) + " comma-separated numbers, got '" + text + "'");
  return out;
}

}  // namespace dmgplace::cli
