#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/formats/stale_inputs.hpp"
#include "dmgplace/runtime.hpp"
#include "dmgplace/tools/validate/deep_validation.hpp"

namespace dmgplace::cli {
namespace {

// Inputs recorded in the header that changed since the bake, one line each.
std::vector<std::string> stale(const std::string& file) {
  std::vector<std::string> out;
  try {
    for (const auto& s : formats::check_inputs(file))
      if (s.changed)
        out.push_back(file + ": input " + s.path + " (found at " + s.at.string() +
                      ") changed since the bake: bake again");
  } catch (const std::exception& e) {
    out.push_back(e.what());
  }
  return out;
}

struct SetCheck {
  std::vector<std::string> errors, warnings;
};

// The three files as one set: one robot, one object, one environment, in any order.
SetCheck check_set(const std::vector<std::string>& files) {
  SetCheck c;
  std::map<std::string, std::string> by_schema;
  for (const auto& f : files) {
    try {
      const std::string schema = formats::H5Reader(f).header().schema;
      if (!by_schema.emplace(schema, f).second)
        c.errors.push_back(f + ": a second " + schema + " artifact in the set (also " + by_schema[schema] + ")");
    } catch (const std::exception& e) {
      c.errors.push_back(e.what());
    }
  }
  for (const char* kind : {"dmgplace.robot", "dmgplace.object", "dmgplace.environment"})
    if (!by_schema.count(kind)) c.errors.push_back(std::string("--set: no ") + kind + " artifact among the files");
  if (!c.errors.empty()) return c;
  try {
    const auto world =
        World::load(by_schema["dmgplace.robot"], by_schema["dmgplace.object"], by_schema["dmgplace.environment"]);
    c.warnings = world->fit_warnings();
  } catch (const std::exception& e) {
    c.errors.push_back(e.what());
  }
  return c;
}

nlohmann::ordered_json deep_json(const tools::DeepReport& r) {
  nlohmann::ordered_json checks = nlohmann::ordered_json::array();
  for (const auto& c : r.checks)
    checks.push_back({{"check", c.name},
                      {"dataset", c.dataset},
                      {"ok", c.ok()},
                      {"samples", c.samples},
                      {"worst", c.worst},
                      {"tolerance", c.tolerance},
                      {"unit", c.unit},
                      {"worst_sample", c.worst_sample}});
  return {{"checks", checks}, {"notes", r.notes}};
}

// --deep on one sound file: its failed checks join `problems`; the report is printed or kept for JSON.
void run_deep(const std::string& f, const ValidateArgs& a, std::vector<std::string>& problems,
              nlohmann::ordered_json* json) {
  tools::DeepOptions o;
  o.samples = a.samples, o.seed = a.seed, o.check_inputs = a.check_inputs;
  try {
    const auto report = tools::deep_validate(f, o);
    for (auto& p : report.problems()) problems.push_back(std::move(p));
    if (json) {
      *json = deep_json(report);
    } else if (!a.quiet) {
      for (const auto& c : report.checks)
        std::cout << f << ": deep: " << (c.ok() ? "ok   " : "FAIL ") << tools::describe(c) << "\n";
      for (const auto& n : report.notes) std::cout << f << ": deep: note: " << n << "\n";
    }
  } catch (const std::exception& e) {
    problems.push_back(e.what());
  }
}

}  // namespace

int run_validate(const ValidateArgs& a) {
  int bad = 0;
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& f : a.files) {
    auto problems = formats::validate_artifact(f);
    if (a.check_inputs && problems.empty())
      for (auto& s : stale(f)) problems.push_back(std::move(s));
    nlohmann::ordered_json deep;
    if (a.deep && problems.empty()) run_deep(f, a, problems, a.json ? &deep : nullptr);
    bad += !problems.empty();
    if (a.json) {
      files.push_back({{"file", f}, {"ok", problems.empty()}, {"problems", problems}});
      if (a.deep) files.back()["deep"] = deep;
      continue;
    }
    for (const auto& p : problems) std::cout << p << "\n";
    if (problems.empty() && !a.quiet) std::cout << f << ": ok\n";
  }
  SetCheck set;
  if (a.set) {
    if (a.files.size() != 3)
      set.errors.push_back("--set takes three artifacts (robot, object, environment), got " +
                           std::to_string(a.files.size()));
    else if (bad == 0) set = check_set(a.files);
    else set.errors.push_back("--set: not checked, a file above is unsound");
  }
  if (a.json) {
    nlohmann::ordered_json j{{"files", files}, {"ok", int(a.files.size()) - bad}, {"bad", bad}};
    if (a.set) j["set"] = {{"ok", set.errors.empty()}, {"errors", set.errors}, {"warnings", set.warnings}};
    std::cout << j.dump(2) << "\n";
  } else if (a.set) {
    for (const auto& e : set.errors) std::cout << "set: error: " << e << "\n";
    for (const auto& w : set.warnings) std::cout << "set: warning: " << w << "\n";
    if (set.errors.empty() && !a.quiet) std::cout << "set: ok (robot, object and environment fit together)\n";
  }
  return bad || !set.errors.empty() ? 1 : 0;
}

}  // namespace dmgplace::cli
