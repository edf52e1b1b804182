#include "dmgplace/formats/artifact_kind.hpp"
#include <algorithm>

#include "dataset_check.hpp"
#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"

namespace dmgplace::formats {
namespace {

template <class Load, class Check>
std::vector<std::string> validate_kind(const std::filesystem::path& path, Load load, Check check) {
  try {
    auto artifact = load(path);
    std::vector<std::string> out;
    for (auto& p : check(artifact)) out.push_back(path.string() + ": " + p);
    return out;
  } catch (const Error& e) {
    return {e.what()};
  }
}

}  // namespace

std::vector<std::string> validate_artifact(const std::filesystem::path& path) {
  std::string schema;
  std::vector<std::string> problems;
  try {
    H5Reader r(path);
    schema = r.header().schema;
    problems = r.verify_all_checksums();
  } catch (const Error& e) {
    return {e.what()};
  }
  std::vector<std::string> more;
  if (schema == kObjectSchema) more = validate_kind(path, read_object_unchecked, check_object);
  else if (schema == kEnvironmentSchema) more = validate_kind(path, read_environment_unchecked, check_environment);
  else if (schema == kRobotSchema) more = validate_kind(path, read_robot_unchecked, check_robot);
  else if (schema == kDatasetSchema) more = detail::check_dataset(path);
  else more = {path.string() + ": schema: unknown artifact kind '" + schema + "'"};
  // A checksum failure also makes loading fail: report each message once.
  for (auto& m : more)
    if (std::find(problems.begin(), problems.end(), m) == problems.end()) problems.push_back(m);
  return problems;
}

Summary inspect_artifact(const std::filesystem::path& path) {
  ArtifactHeader h;
  {
    H5Reader r(path);
    h = r.header();
  }
  Summary s;
  s.emplace_back("file", path.string());
  s.emplace_back("schema", h.schema + " v" + std::to_string(h.schema_version));
  s.emplace_back("tool_version", h.tool_version);
  s.emplace_back("created_utc", h.created_utc);
  s.emplace_back("parameters", h.parameters_json);
  for (const auto& in : h.inputs) s.emplace_back("input", in.sha256 + "  " + in.path);
  Summary body;
  if (h.schema == kObjectSchema) body = summarize_object(load_object(path));
  else if (h.schema == kEnvironmentSchema) body = summarize_environment(load_environment(path));
  else if (h.schema == kRobotSchema) body = summarize_robot(load_robot(path));
  else throw Error(path.string(), "schema", "unknown artifact kind '" + h.schema + "'");
  s.insert(s.end(), body.begin(), body.end());
  return s;
}

}  // namespace dmgplace::formats
