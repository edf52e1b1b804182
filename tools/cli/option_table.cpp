#include "option_table.hpp"

namespace dmgplace::cli {

nlohmann::ordered_json option_parameters(const OptionTable& table) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& row : table)
    if (!row.param.empty()) std::visit([&](auto* v) { j[row.param] = *v; }, row.value);
  return j;
}

}  // namespace dmgplace::cli
