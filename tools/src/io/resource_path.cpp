#include "dmgplace/tools/io/resource_path.hpp"

#include <system_error>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;

namespace {

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Checks one candidate and records it.
bool try_candidate(const fs::path& p, std::vector<fs::path>* tried) {
  if (tried) tried->push_back(p);
  return is_file(p);
}

}  // namespace

fs::path resolve_resource(const std::string& uri, const fs::path& base_dir, const std::vector<fs::path>& package_paths,
                          std::vector<fs::path>* tried) {
  static const std::string kPackage = "package://", kFile = "file://";
  if (uri.rfind(kPackage, 0) == 0) {
    const std::string body = uri.substr(kPackage.size());
    const auto slash = body.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == body.size()) return {};
    const std::string name = body.substr(0, slash);
    const fs::path rest = fs::path(body.substr(slash + 1)).relative_path().lexically_normal();
    // A package resource stays inside its package: package://pkg/../../etc/passwd is refused.
    if (rest.empty() || *rest.begin() == "..")
      throw Error(uri, "", "a package:// path may not leave its package folder");
    for (const auto& pp : package_paths) {
      if (try_candidate(pp / name / rest, tried)) return pp / name / rest;
      if (try_candidate(pp / rest, tried)) return pp / rest;
    }
    // A checkout usually keeps the URDF inside its own package: look upwards for a folder NAME.
    std::error_code ec;
    fs::path dir = fs::absolute(base_dir.empty() ? fs::path(".") : base_dir, ec).lexically_normal();
    for (; !dir.empty(); dir = dir.parent_path()) {
      if (dir.filename() == name && try_candidate(dir / rest, tried)) return dir / rest;
      if (dir == dir.parent_path()) break;
    }
    return {};
  }
  fs::path p = uri.rfind(kFile, 0) == 0 ? fs::path(uri.substr(kFile.size())) : fs::path(uri);
  if (p.empty()) return {};
  if (p.is_relative()) p = base_dir / p;
  return try_candidate(p, tried) ? p : fs::path();
}

std::string describe_candidates(const std::vector<fs::path>& tried) {
  std::string s;
  for (const auto& p : tried) s += (s.empty() ? "" : ", ") + p.string();
  return s.empty() ? std::string("nothing to look at") : s;
}

}  // namespace dmgplace::tools
