#pragma once
// One row per command-line option: its flag, where its value lives (a field of the library's own
// option struct), range, unit and help. main.cpp binds the rows to CLI11 (help shows each default,
// unit and range); the artifact header's `parameters` are written from the same rows, so a new
// option is one line and the header cannot disagree with what ran.
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

namespace dmgplace::cli {

struct OptionRow {
  using Value = std::variant<double*, int*, bool*, std::string*, std::vector<std::string>*>;
  // A row reads as its fields in order; `choices` may be left out.
  OptionRow(std::string flag_, std::string param_, Value value_, double lo_, double hi_, std::string unit_,
            std::string help_, std::vector<std::string> choices_ = {})
      : flag(std::move(flag_)), param(std::move(param_)), value(value_), lo(lo_), hi(hi_), unit(std::move(unit_)),
        help(std::move(help_)), choices(std::move(choices_)) {}
  std::string flag;   // "--seed-resolution"
  std::string param;  // key in the header's parameters ("" : not recorded, e.g. --json)
  Value value;
  double lo = 0, hi = 0;  // range of a number, checked at parse time
  std::string unit;       // "m", "deg", "rad", ... ("" for none)
  std::string help;
  std::vector<std::string> choices;  // allowed words of a text option (empty: any text)
};
using OptionTable = std::vector<OptionRow>;

// {param: value} for every row with a param, in row order.
nlohmann::ordered_json option_parameters(const OptionTable& table);

}  // namespace dmgplace::cli
