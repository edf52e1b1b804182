#include "dmgplace/tools/io/yaml_file.hpp"

#include <set>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

// Depth-first over the document: the first key that appears twice in one map. Recursion depth is
// bounded by yaml-cpp's own nesting limit.
void refuse_duplicates(const YAML::Node& n, const std::string& file) {
  if (n.IsMap()) {
    std::set<std::string> keys;
    for (const auto& kv : n) {
      if (kv.first.IsScalar() && !keys.insert(kv.first.Scalar()).second)
        throw Error(file, yaml_line(kv.first), "duplicate key '" + kv.first.Scalar() + "'");
      refuse_duplicates(kv.second, file);
    }
  } else if (n.IsSequence()) {
    for (const auto& item : n) refuse_duplicates(item, file);
  }
}

}  // namespace

std::string yaml_line(const YAML::Node& n) {
  const auto m = n.Mark();
  return m.is_null() ? std::string() : "line " + std::to_string(m.line + 1);
}

YAML::Node load_yaml_file(const std::filesystem::path& path) {
  const std::string file = path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw Error(file, "", "cannot read the file");
  } catch (const YAML::Exception& e) {
    throw Error(file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1), "not valid YAML: " + e.msg);
  }
  refuse_duplicates(root, file);
  return root;
}

void require_known_keys(const YAML::Node& n, std::initializer_list<const char*> allowed, const std::string& file,
                        const std::string& where) {
  if (!n.IsMap()) return;
  for (const auto& kv : n) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<non-scalar key>");
    bool known = false;
    for (const char* a : allowed) known |= key == a;
    if (known) continue;
    std::string list;
    for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    const std::string line = yaml_line(kv.first);
    throw Error(file, (where.empty() ? key : where + "." + key) + (line.empty() ? "" : " (" + line + ")"),
                "unknown key (expected one of: " + list + ")");
  }
}

}  // namespace dmgplace::tools
