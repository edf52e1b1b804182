#include "dmgplace/tools/io/yaml_file.hpp"

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

YAML::Node load_yaml_file(const std::filesystem::path& path) {
  const std::string file = path.string();
  try {
    return YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw Error(file, "", "cannot read the file");
  } catch (const YAML::Exception& e) {
    throw Error(file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1), "not valid YAML: " + e.msg);
  }
}

}  // namespace dmgplace::tools
