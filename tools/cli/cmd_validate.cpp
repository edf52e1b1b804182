#include <iostream>

#include "commands.hpp"
#include "dmgplace/formats/artifact_kind.hpp"

namespace dmgplace::cli {

int run_validate(const ValidateArgs& a) {
  int bad = 0;
  for (const auto& f : a.files) {
    auto problems = formats::validate_artifact(f);
    for (const auto& p : problems) std::cout << p << "\n";
    if (problems.empty() && !a.quiet) std::cout << f << ": ok\n";
    bad += !problems.empty();
  }
  return bad ? 1 : 0;
}

}  // namespace dmgplace::cli
