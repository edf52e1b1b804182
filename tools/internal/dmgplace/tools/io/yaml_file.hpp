#pragma once
// Loads a YAML file, turning yaml-cpp's exceptions into a dmgplace::Error that names the file
// (and the line of a syntax error). Duplicate keys anywhere in the document are refused: yaml-cpp
// keeps one of them silently, so `seed: 1` twice would run with whichever it kept.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <initializer_list>
#include <string>

namespace dmgplace::tools {

YAML::Node load_yaml_file(const std::filesystem::path& path);

// "line N" of a node (1-based), or "" when yaml-cpp has no mark for it.
std::string yaml_line(const YAML::Node& n);

// Refuses any key of map `n` not in `allowed`, naming the key, its line and the keys allowed
// (a typo such as `wieght` must not be ignored). `where` is the map's element name ("" for the root).
void require_known_keys(const YAML::Node& n, std::initializer_list<const char*> allowed, const std::string& file,
                        const std::string& where);

}  // namespace dmgplace::tools
