#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "dmgplace/formats/artifact_kind.hpp"

namespace dmgplace::cli {

int run_validate(const ValidateArgs& a) {
  int bad = 0;
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& f : a.files) {
    auto problems = formats::validate_artifact(f);
    bad += !problems.empty();
    if (a.json) {
      files.push_back({{"file", f}, {"ok", problems.empty()}, {"problems", problems}});
      continue;
    }
    for (const auto& p : problems) std::cout << p << "\n";
    if (problems.empty() && !a.quiet) std::cout << f << ": ok\n";
  }
  if (a.json)
    std::cout << nlohmann::ordered_json{{"files", files}, {"ok", int(a.files.size()) - bad}, {"bad", bad}}.dump(2) << "\n";
  return bad ? 1 : 0;
}

}  // namespace dmgplace::cli
