#include "dmgplace/tools/system/file_names.hpp"

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

bool is_safe_file_name(const std::string& name) {
  if (name.empty() || name == "." || name == "..") return false;
  for (const char c : name) {
    // Spelled out rather than std::isalnum, whose answer depends on the locale.
    const bool letter = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'), digit = c >= '0' && c <= '9';
    if (!letter && !digit && c != '.' && c != '_' && c != '-') return false;
  }
  return true;
}

void check_file_name_component(const std::string& name, const std::string& file, const std::string& element) {
  if (is_safe_file_name(name)) return;
  throw Error(file, element,
              "'" + name +
                  "' must be a non-empty word of letters, digits, '.', '_' and '-' (not '.' or '..'): "
                  "it names a file or folder");
}

}  // namespace dmgplace::tools
