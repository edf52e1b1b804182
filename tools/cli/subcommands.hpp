#pragma once
// The subcommands of `dmgplace`: each registers its options on the CLI11 app and runs with what
// was parsed. With main.cpp, the only code that sees CLI11.
#include <functional>
#include <vector>

namespace CLI {
class App;
}

namespace dmgplace::cli {

struct Subcommand {
  CLI::App* app = nullptr;  // parsed when *app is true
  std::function<int()> run;
};

// Every subcommand, in the order of the help.
std::vector<Subcommand> add_subcommands(CLI::App& app);

}  // namespace dmgplace::cli
