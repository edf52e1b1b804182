#pragma once
// Resolves the file names found inside URDF and scene files (relative, file://, package://).
#include <filesystem>
#include <string>
#include <vector>

namespace dmgplace::tools {

// Returns the existing file `uri` names, or an empty path when none exists.
// - "package://NAME/rest": NAME/rest then rest under each package path, then every ancestor of
//   `base_dir` (itself included) that is named NAME, joined with rest.
// - "file:///abs" and absolute paths as they are; anything else relative to `base_dir`.
// Every candidate looked at is appended to `tried` (when given), for the error message.
// Throws dmgplace::Error when a package:// path leaves its package (`..`).
std::filesystem::path resolve_resource(const std::string& uri, const std::filesystem::path& base_dir,
                                       const std::vector<std::filesystem::path>& package_paths,
                                       std::vector<std::filesystem::path>* tried = nullptr);

// "a, b, c" of the candidates, for error messages.
std::string describe_candidates(const std::vector<std::filesystem::path>& tried);

}  // namespace dmgplace::tools
