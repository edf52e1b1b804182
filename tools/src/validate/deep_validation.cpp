#include "dmgplace/tools/validate/deep_validation.hpp"

#include <iomanip>
#include <sstream>

#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/h5_reader.hpp"
#include "dmgplace/tools/validate/deep_checks.hpp"

namespace dmgplace::tools {

namespace detail {

std::string fmt(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

std::string fmt(const Eigen::Vector3d& p) { return "(" + fmt(p.x()) + ", " + fmt(p.y()) + ", " + fmt(p.z()) + ")"; }

}  // namespace detail

bool DeepReport::ok() const {
  for (const auto& c : checks)
    if (!c.ok()) return false;
  return true;
}

std::string describe(const DeepCheck& c) {
  return c.name + ": worst " + detail::fmt(c.worst) + " " + c.unit + " (tolerance " + detail::fmt(c.tolerance) + " " +
         c.unit + ", " + std::to_string(c.samples) + " samples)" +
         (c.worst_sample.empty() ? "" : " at " + c.worst_sample);
}

std::vector<std::string> DeepReport::problems() const {
  std::vector<std::string> out;
  for (const auto& c : checks)
    if (!c.ok()) out.push_back(file + ": " + c.dataset + ": --deep: " + describe(c));
  return out;
}

DeepReport deep_validate(const std::filesystem::path& file, const DeepOptions& o) {
  if (o.samples < 1) throw Error(file.string(), "--samples", "must be at least 1");
  // The loaders below are the ordinary validation's gate: an unsound file is refused there.
  DeepReport report;
  report.file = file.string();
  report.schema = formats::H5Reader(file).header().schema;
  if (report.schema == formats::kEnvironmentSchema) {
    detail::deep_environment(formats::load_environment(file), o, report);
  } else if (report.schema == formats::kRobotSchema) {
    const auto robot = formats::load_robot(file);
    detail::deep_robot(robot, o, report);
    if (o.check_inputs) detail::robot_against_inputs(robot, file, report);
  } else if (report.schema == formats::kObjectSchema) {
    const auto object = formats::load_object(file);
    detail::deep_object(object, o, report);
    if (o.check_inputs) detail::object_against_inputs(object, file, report);
  } else {
    report.notes.push_back("no deep checks for " + report.schema + " files");
  }
  return report;
}

}  // namespace dmgplace::tools
