#pragma once
// Names from input files (an experiment's problem names, ...) that become file or folder names.
// Only a whitelist is safe everywhere: no '/' or ".." to leave the folder, no space, quote or '$'
// for a tool that might one day meet the path, nothing the file system would refuse.
#include <string>

namespace dmgplace::tools {

// True when `name` is one path component of [A-Za-z0-9._-], not empty, "." or "..".
bool is_safe_file_name(const std::string& name);

// Throws dmgplace::Error "FILE: ELEMENT: 'NAME' must be a non-empty word of ..." unless
// is_safe_file_name(name); `file` and `element` say where the name came from.
void check_file_name_component(const std::string& name, const std::string& file, const std::string& element);

}  // namespace dmgplace::tools
