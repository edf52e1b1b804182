#pragma once
// Loads a YAML file, turning yaml-cpp's exceptions into a dmgplace::Error that names the file
// (and the line of a syntax error).
#include <yaml-cpp/yaml.h>

#include <filesystem>

namespace dmgplace::tools {

YAML::Node load_yaml_file(const std::filesystem::path& path);

}  // namespace dmgplace::tools
