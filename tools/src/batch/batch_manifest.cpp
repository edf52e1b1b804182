#include "dmgplace/tools/batch/batch_manifest.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fnmatch.h>
#include <map>
#include <set>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/placement/placement_query.hpp"
#include "dmgplace/tools/io/yaml_file.hpp"
#include "dmgplace/tools/system/file_names.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;
namespace {

struct Reader {
  std::string file;
  fs::path dir;

  [[noreturn]] void fail(const std::string& where, const std::string& why) const { throw Error(file, where, why); }

  // A path relative to the manifest's folder that must name an existing file (or folder).
  fs::path existing(const YAML::Node& n, const std::string& where, bool folder = false) const {
    if (!n || !n.IsScalar() || n.Scalar().empty()) fail(where, folder ? "expected a folder" : "expected a file path");
    const fs::path p = fs::path(n.Scalar()).is_absolute() ? fs::path(n.Scalar()) : dir / n.Scalar();
    std::error_code ec;
    if (!(folder ? fs::is_directory(p, ec) : fs::is_regular_file(p, ec)))
      fail(where, std::string(folder ? "no such folder: " : "no such file: ") + p.string());
    return p;
  }
  std::vector<std::string> flags(const YAML::Node& n, const std::string& where) const {
    if (!n) return {};
    if (!n.IsSequence()) fail(where, "expected a list of command-line arguments");
    std::vector<std::string> out;
    for (const auto& f : n) {
      if (!f.IsScalar()) fail(where, "expected a list of command-line arguments");
      if (f.Scalar() == "--out") fail(where, "--out is the batch's to choose");
      out.push_back(f.Scalar());
    }
    return out;
  }
  std::vector<std::string> names(const YAML::Node& n, const std::string& where) const {
    if (!n || !n.IsSequence() || n.size() == 0) fail(where, "expected a non-empty list of names");
    std::vector<std::string> out;
    for (const auto& x : n) out.push_back(x.as<std::string>());
    return out;
  }
  std::vector<double> numbers(const YAML::Node& n, std::size_t count, const std::string& where) const {
    if (!n || !n.IsSequence() || (count && n.size() != count))
      fail(where, count ? "expected " + std::to_string(count) + " numbers" : "expected a list of numbers");
    std::vector<double> v;
    for (const auto& x : n) {
      const double d = x.as<double>();
      if (!std::isfinite(d)) fail(where, "not a finite number");
      v.push_back(d);
    }
    return v;
  }
};

// Files matching `pattern` (a path whose last components may hold * ? [..]), sorted.
std::vector<fs::path> glob(const fs::path& dir, const std::string& pattern) {
  std::vector<fs::path> out;
  std::error_code ec;
  const fs::path base = fs::path(pattern).is_absolute() ? fs::path("/") : dir;
  for (auto it = fs::recursive_directory_iterator(base, fs::directory_options::skip_permission_denied, ec);
       it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) break;
    if (!it->is_regular_file(ec)) continue;
    const std::string rel =
        fs::path(pattern).is_absolute() ? it->path().string() : it->path().lexically_relative(dir).string();
    if (::fnmatch(pattern.c_str(), rel.c_str(), FNM_PATHNAME) == 0) out.push_back(it->path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

BatchManifest read_batch_manifest(const fs::path& path) {
  Reader r{path.string(), path.parent_path()};
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap()) r.fail("", "expected a map (name, robots, objects, environments, queries)");
  require_known_keys(root, {"name", "robots", "objects", "environments", "queries"}, r.file, "");
  BatchManifest m;
  m.path = path;
  try {
    m.name = root["name"] ? root["name"].as<std::string>() : path.stem().string();
    std::map<std::string, std::set<std::string>> defined;  // kind -> names
    const auto each = [&](const char* key, const char* kind, auto&& read) {
      const YAML::Node n = root[key];
      if (!n) return;
      if (!n.IsMap()) r.fail(key, "expected a map of name: {...}");
      // Sorted by name. Names only: assigning a YAML::Node (as std::sort would) overwrites the node
      // it refers to, so the nodes are looked up again by name.
      std::vector<std::string> names;
      for (const auto& kv : n) names.push_back(kv.first.as<std::string>());
      std::sort(names.begin(), names.end());
      for (const auto& name : names) {
        const YAML::Node node = n[name];
        const std::string where = std::string(key) + "." + name;
        check_file_name_component(name, r.file, where);
        if (!node.IsMap()) r.fail(where, "expected a map");
        read(name, node, where, kind);
      }
    };
    // Robots and environments both take package:// roots and extra bake flags.
    auto add_package_path_and_flags = [&](BatchBake& b, const YAML::Node& n, const std::string& where) {
      if (n["package_path"])
        b.args.insert(b.args.end(),
                      {"--package-path", r.existing(n["package_path"], where + ".package_path", true).string()});
      for (auto& f : r.flags(n["flags"], where + ".flags")) b.args.push_back(f);
    };
    each("robots", "robot",
         [&](const std::string& name, const YAML::Node& n, const std::string& where, const char* kind) {
           require_known_keys(n, {"urdf", "srdf", "arm", "package_path", "flags"}, r.file, where);
           BatchBake b{kind, name, {}, {}};
           const fs::path urdf = r.existing(n["urdf"], where + ".urdf");
           b.args = {urdf.string()};
           b.inputs = {urdf};
           if (n["srdf"]) {
             const fs::path srdf = r.existing(n["srdf"], where + ".srdf");
             b.args.insert(b.args.end(), {"--srdf", srdf.string()});
             b.inputs.push_back(srdf);
           }
           if (!n["arm"]) r.fail(where, "needs arm: BASE_LINK:TIP_LINK");
           b.args.insert(b.args.end(), {"--arm", n["arm"].as<std::string>()});
           add_package_path_and_flags(b, n, where);
           m.bakes.push_back(b);
           defined[kind].insert(name);
         });
    each("objects", "object",
         [&](const std::string& name, const YAML::Node& n, const std::string& where, const char* kind) {
           require_known_keys(n, {"mesh", "glob", "flags"}, r.file, where);
           const auto flags = r.flags(n["flags"], where + ".flags");
           std::vector<std::pair<std::string, fs::path>> meshes;
           if (n["mesh"]) meshes.emplace_back(name, r.existing(n["mesh"], where + ".mesh"));
           else if (n["glob"]) {
             for (const auto& p : glob(r.dir, n["glob"].as<std::string>())) {
               std::string sub = p.parent_path().filename().string();
               std::replace_if(
                   sub.begin(), sub.end(),
                   [](char c) { return !(std::isalnum((unsigned char)c) || c == '.' || c == '_' || c == '-'); }, '_');
               meshes.emplace_back(name + "." + sub, p);
             }
             if (meshes.empty()) r.fail(where + ".glob", "matches no file");
           } else {
             r.fail(where, "needs mesh: FILE or glob: PATTERN");
           }
           for (const auto& [object, mesh] : meshes) {
             BatchBake b{kind, object, {mesh.string()}, {mesh}};
             b.args.insert(b.args.end(), flags.begin(), flags.end());
             if (!defined[kind].insert(object).second) r.fail(where, "object '" + object + "' defined twice");
             m.bakes.push_back(b);
           }
           defined["object-group"].insert(name);
         });
    each("environments", "environment",
         [&](const std::string& name, const YAML::Node& n, const std::string& where, const char* kind) {
           require_known_keys(n, {"scene", "volume", "package_path", "flags"}, r.file, where);
           const fs::path scene = r.existing(n["scene"], where + ".scene");
           const auto v = r.numbers(n["volume"], 6, where + ".volume");
           std::string volume;
           for (double x : v) volume += (volume.empty() ? "" : ",") + runtime::number_text(x);
           BatchBake b{kind, name, {scene.string(), "--volume", volume}, {scene}};
           add_package_path_and_flags(b, n, where);
           m.bakes.push_back(b);
           defined[kind].insert(name);
         });
    const YAML::Node qs = root["queries"];
    if (qs && !qs.IsSequence()) r.fail("queries", "expected a list of query templates");
    std::set<std::string> template_names;
    for (std::size_t i = 0; qs && i < qs.size(); ++i) {
      const YAML::Node q = qs[i];
      const std::string where = "queries[" + std::to_string(i) + "]";
      require_known_keys(q,
                         {"name", "robot", "objects", "environments", "initial_grasps", "start", "variants", "seeds",
                          "time_limit", "iterations", "query", "runs"},
                         r.file, where);
      if (q["runs"] && (q["objects"] || q["environments"] || q["variants"] || q["seeds"]))
        r.fail(where,
               "either runs: (an explicit list) or objects/environments/variants/seeds (their product), not both");
      BatchQueryTemplate t;
      t.name = q["name"] ? q["name"].as<std::string>() : "q" + std::to_string(i);
      check_file_name_component(t.name, r.file, where + ".name");
      if (!template_names.insert(t.name).second) r.fail(where + ".name", "'" + t.name + "' appears twice");
      t.robot = q["robot"] ? q["robot"].as<std::string>() : "";
      if (!defined["robot"].count(t.robot)) r.fail(where + ".robot", "no robot '" + t.robot + "' in robots");
      for (const auto& o : q["runs"] ? std::vector<std::string>{} : r.names(q["objects"], where + ".objects")) {
        if (defined["object"].count(o)) t.objects.push_back(o);
        else if (defined["object-group"].count(o)) {  // a glob: every object it made
          for (const auto& b : m.bakes)
            if (b.kind == "object" && b.name.rfind(o + ".", 0) == 0) t.objects.push_back(b.name);
        } else {
          r.fail(where + ".objects", "no object '" + o + "' in objects");
        }
      }
      for (const auto& e :
           q["runs"] ? std::vector<std::string>{} : r.names(q["environments"], where + ".environments")) {
        if (!defined["environment"].count(e))
          r.fail(where + ".environments", "no environment '" + e + "' in environments");
        t.environments.push_back(e);
      }
      const YAML::Node g = q["initial_grasps"];
      if (!g || !g.IsMap() || g.size() == 0)
        r.fail(where + ".initial_grasps", "expected a map name: [x, y, z, qx, qy, qz, qw]");
      for (const auto& kv : g) {
        const std::string gname = kv.first.as<std::string>();
        check_file_name_component(gname, r.file, where + ".initial_grasps");
        const auto p = r.numbers(kv.second, 7, where + ".initial_grasps." + gname);
        t.grasps.push_back({gname, {p[0], p[1], p[2], p[3], p[4], p[5], p[6]}});
      }
      t.start = r.numbers(q["start"], 0, where + ".start");
      if (q["variants"]) {
        t.variants = r.names(q["variants"], where + ".variants");
        for (const auto& v : t.variants)
          if (!runtime::parse_variant(v))
            r.fail(where + ".variants", "unknown variant '" + v + "' (full, random-grasp, no-regrasp)");
      }
      if (q["seeds"]) t.seeds = q["seeds"].as<int>();
      if (t.seeds < 1 || t.seeds > 100000) r.fail(where + ".seeds", "must be in [1, 100000]");
      if (q["time_limit"]) t.time_limit = q["time_limit"].as<double>();
      if (!(t.time_limit >= 0 && t.time_limit <= 1e6)) r.fail(where + ".time_limit", "must be in [0, 1e6] s");
      if (q["iterations"]) t.iterations = q["iterations"].as<long>();
      if (t.iterations < 0 || t.iterations > 1000000000) r.fail(where + ".iterations", "must be in [0, 1e9]");
      if (const YAML::Node extra = q["query"]) {
        if (!extra.IsMap()) r.fail(where + ".query", "expected a map of query-file keys");
        require_known_keys(extra, {"volume", "objective", "options"}, r.file, where + ".query");
        YAML::Emitter e;
        e << extra;
        t.extra_yaml = e.c_str();
      }
      if (const YAML::Node runs = q["runs"]) {
        if (!runs.IsSequence() || runs.size() == 0) r.fail(where + ".runs", "expected a non-empty list of runs");
        for (std::size_t k = 0; k < runs.size(); ++k) {
          const YAML::Node x = runs[k];
          const std::string rw = where + ".runs[" + std::to_string(k) + "]";
          require_known_keys(x, {"object", "environment", "grasp", "variant", "seed"}, r.file, rw);
          BatchRun run;
          run.object = x["object"] ? x["object"].as<std::string>() : "";
          run.environment = x["environment"] ? x["environment"].as<std::string>() : "";
          run.grasp = x["grasp"] ? x["grasp"].as<std::string>() : "";
          run.variant = x["variant"] ? x["variant"].as<std::string>() : "full";
          run.seed = x["seed"] ? x["seed"].as<int>() : 1;
          if (!defined["object"].count(run.object)) r.fail(rw + ".object", "no object '" + run.object + "' in objects");
          if (!defined["environment"].count(run.environment))
            r.fail(rw + ".environment", "no environment '" + run.environment + "' in environments");
          if (std::none_of(t.grasps.begin(), t.grasps.end(), [&](const auto& g) { return g.first == run.grasp; }))
            r.fail(rw + ".grasp", "no grasp '" + run.grasp + "' in initial_grasps");
          if (!runtime::parse_variant(run.variant)) r.fail(rw + ".variant", "unknown variant '" + run.variant + "'");
          if (run.seed < 1) r.fail(rw + ".seed", "must be >= 1");
          t.runs.push_back(run);
        }
      } else {
        for (const auto& object : t.objects)
          for (const auto& env : t.environments)
            for (const auto& grasp : t.grasps)
              for (const auto& variant : t.variants)
                for (int seed = 1; seed <= t.seeds; ++seed) t.runs.push_back({object, env, grasp.first, variant, seed});
      }
      m.queries.push_back(std::move(t));
    }
  } catch (const YAML::Exception& e) {
    throw Error(r.file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1),
                "malformed manifest: " + e.msg);
  }
  if (m.bakes.empty()) r.fail("", "nothing to bake (robots, objects, environments are all empty)");
  return m;
}

}  // namespace dmgplace::tools
