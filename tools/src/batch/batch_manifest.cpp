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

// The manifest's sections in turn, into `m`; `defined` holds the names each kind declared so
// the query templates can refer to them ("object-group": a glob's name, standing for its objects).
struct ManifestReader : Reader {
  BatchManifest m;
  std::map<std::string, std::set<std::string>> defined;

  // Each name: {...} of a section, sorted by name. Names only: assigning a YAML::Node (as
  // std::sort would) overwrites the node it refers to, so the nodes are looked up again by name.
  template <class Read>
  void each(const YAML::Node& root, const char* key, Read&& read) {
    const YAML::Node n = root[key];
    if (!n) return;
    if (!n.IsMap()) fail(key, "expected a map of name: {...}");
    std::vector<std::string> names;
    for (const auto& kv : n) names.push_back(kv.first.as<std::string>());
    std::sort(names.begin(), names.end());
    for (const auto& name : names) {
      const YAML::Node node = n[name];
      const std::string where = std::string(key) + "." + name;
      check_file_name_component(name, file, where);
      if (!node.IsMap()) fail(where, "expected a map");
      read(name, node, where);
    }
  }

  // Robots and environments both take package:// roots and extra bake flags.
  void add_package_path_and_flags(BatchBake& b, const YAML::Node& n, const std::string& where) const {
    if (n["package_path"])
      b.args.insert(b.args.end(),
                    {"--package-path", existing(n["package_path"], where + ".package_path", true).string()});
    for (auto& f : flags(n["flags"], where + ".flags")) b.args.push_back(f);
  }

  void robot(const std::string& name, const YAML::Node& n, const std::string& where) {
    require_known_keys(n, {"urdf", "srdf", "arm", "package_path", "flags"}, file, where);
    BatchBake b{"robot", name, {}, {}};
    const fs::path urdf = existing(n["urdf"], where + ".urdf");
    b.args = {urdf.string()};
    b.inputs = {urdf};
    if (n["srdf"]) {
      const fs::path srdf = existing(n["srdf"], where + ".srdf");
      b.args.insert(b.args.end(), {"--srdf", srdf.string()});
      b.inputs.push_back(srdf);
    }
    if (!n["arm"]) fail(where, "needs arm: BASE_LINK:TIP_LINK");
    b.args.insert(b.args.end(), {"--arm", n["arm"].as<std::string>()});
    add_package_path_and_flags(b, n, where);
    m.bakes.push_back(b);
    defined["robot"].insert(name);
  }

  // One mesh, or every file a glob matches (each named NAME.<its folder>).
  void objects(const std::string& name, const YAML::Node& n, const std::string& where) {
    require_known_keys(n, {"mesh", "glob", "flags"}, file, where);
    const auto extra = flags(n["flags"], where + ".flags");
    std::vector<std::pair<std::string, fs::path>> meshes;
    if (n["mesh"]) {
      meshes.emplace_back(name, existing(n["mesh"], where + ".mesh"));
    } else if (n["glob"]) {
      for (const auto& p : glob(dir, n["glob"].as<std::string>())) {
        std::string sub = p.parent_path().filename().string();
        std::replace_if(
            sub.begin(), sub.end(),
            [](char c) { return !(std::isalnum((unsigned char)c) || c == '.' || c == '_' || c == '-'); }, '_');
        meshes.emplace_back(name + "." + sub, p);
      }
      if (meshes.empty()) fail(where + ".glob", "matches no file");
    } else {
      fail(where, "needs mesh: FILE or glob: PATTERN");
    }
    for (const auto& [object, mesh] : meshes) {
      BatchBake b{"object", object, {mesh.string()}, {mesh}};
      b.args.insert(b.args.end(), extra.begin(), extra.end());
      if (!defined["object"].insert(object).second) fail(where, "object '" + object + "' defined twice");
      m.bakes.push_back(b);
    }
    defined["object-group"].insert(name);
  }

  void environment(const std::string& name, const YAML::Node& n, const std::string& where) {
    require_known_keys(n, {"scene", "volume", "package_path", "flags"}, file, where);
    const fs::path scene = existing(n["scene"], where + ".scene");
    const auto v = numbers(n["volume"], 6, where + ".volume");
    std::string volume;
    for (double x : v) volume += (volume.empty() ? "" : ",") + runtime::number_text(x);
    BatchBake b{"environment", name, {scene.string(), "--volume", volume}, {scene}};
    add_package_path_and_flags(b, n, where);
    m.bakes.push_back(b);
    defined["environment"].insert(name);
  }

  // The objects (a glob's name stands for every object it made) and environments a template crosses.
  void template_grid(BatchQueryTemplate& t, const YAML::Node& q, const std::string& where) {
    if (q["runs"]) return;
    for (const auto& o : names(q["objects"], where + ".objects")) {
      if (defined["object"].count(o)) {
        t.objects.push_back(o);
      } else if (defined["object-group"].count(o)) {
        for (const auto& b : m.bakes)
          if (b.kind == "object" && b.name.rfind(o + ".", 0) == 0) t.objects.push_back(b.name);
      } else {
        fail(where + ".objects", "no object '" + o + "' in objects");
      }
    }
    for (const auto& e : names(q["environments"], where + ".environments")) {
      if (!defined["environment"].count(e)) fail(where + ".environments", "no environment '" + e + "' in environments");
      t.environments.push_back(e);
    }
  }

  void template_grasps(BatchQueryTemplate& t, const YAML::Node& q, const std::string& where) const {
    const YAML::Node g = q["initial_grasps"];
    if (!g || !g.IsMap() || g.size() == 0)
      fail(where + ".initial_grasps", "expected a map name: [x, y, z, qx, qy, qz, qw]");
    for (const auto& kv : g) {
      const std::string gname = kv.first.as<std::string>();
      check_file_name_component(gname, file, where + ".initial_grasps");
      const auto p = numbers(kv.second, 7, where + ".initial_grasps." + gname);
      t.grasps.push_back({gname, {p[0], p[1], p[2], p[3], p[4], p[5], p[6]}});
    }
  }

  // Variants, seeds, limits and the query-file keys every run of the template gets.
  void template_settings(BatchQueryTemplate& t, const YAML::Node& q, const std::string& where) const {
    t.start = numbers(q["start"], 0, where + ".start");
    if (q["variants"]) {
      t.variants = names(q["variants"], where + ".variants");
      for (const auto& v : t.variants)
        if (!runtime::parse_variant(v))
          fail(where + ".variants", "unknown variant '" + v + "' (full, random-grasp, no-regrasp)");
    }
    if (q["seeds"]) t.seeds = q["seeds"].as<int>();
    if (t.seeds < 1 || t.seeds > 100000) fail(where + ".seeds", "must be in [1, 100000]");
    if (q["time_limit"]) t.time_limit = q["time_limit"].as<double>();
    if (!(t.time_limit >= 0 && t.time_limit <= 1e6)) fail(where + ".time_limit", "must be in [0, 1e6] s");
    if (q["iterations"]) t.iterations = q["iterations"].as<long>();
    if (t.iterations < 0 || t.iterations > 1000000000) fail(where + ".iterations", "must be in [0, 1e9]");
    if (const YAML::Node extra = q["query"]) {
      if (!extra.IsMap()) fail(where + ".query", "expected a map of query-file keys");
      require_known_keys(extra, {"volume", "objective", "options"}, file, where + ".query");
      YAML::Emitter e;
      e << extra;
      t.extra_yaml = e.c_str();
    }
  }

  // An explicit list of runs, each naming what it uses.
  void explicit_runs(BatchQueryTemplate& t, const YAML::Node& runs, const std::string& where) {
    if (!runs.IsSequence() || runs.size() == 0) fail(where + ".runs", "expected a non-empty list of runs");
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const YAML::Node x = runs[k];
      const std::string rw = where + ".runs[" + std::to_string(k) + "]";
      require_known_keys(x, {"object", "environment", "grasp", "variant", "seed"}, file, rw);
      BatchRun run;
      run.object = x["object"] ? x["object"].as<std::string>() : "";
      run.environment = x["environment"] ? x["environment"].as<std::string>() : "";
      run.grasp = x["grasp"] ? x["grasp"].as<std::string>() : "";
      run.variant = x["variant"] ? x["variant"].as<std::string>() : "full";
      run.seed = x["seed"] ? x["seed"].as<int>() : 1;
      if (!defined["object"].count(run.object)) fail(rw + ".object", "no object '" + run.object + "' in objects");
      if (!defined["environment"].count(run.environment))
        fail(rw + ".environment", "no environment '" + run.environment + "' in environments");
      if (std::none_of(t.grasps.begin(), t.grasps.end(), [&](const auto& g) { return g.first == run.grasp; }))
        fail(rw + ".grasp", "no grasp '" + run.grasp + "' in initial_grasps");
      if (!runtime::parse_variant(run.variant)) fail(rw + ".variant", "unknown variant '" + run.variant + "'");
      if (run.seed < 1) fail(rw + ".seed", "must be >= 1");
      t.runs.push_back(run);
    }
  }

  void query_template(const YAML::Node& q, std::size_t i, std::set<std::string>& taken) {
    const std::string where = "queries[" + std::to_string(i) + "]";
    require_known_keys(q,
                       {"name", "robot", "objects", "environments", "initial_grasps", "start", "variants", "seeds",
                        "time_limit", "iterations", "query", "runs"},
                       file, where);
    if (q["runs"] && (q["objects"] || q["environments"] || q["variants"] || q["seeds"]))
      fail(where, "either runs: (an explicit list) or objects/environments/variants/seeds (their product), not both");
    BatchQueryTemplate t;
    t.name = q["name"] ? q["name"].as<std::string>() : "q" + std::to_string(i);
    check_file_name_component(t.name, file, where + ".name");
    if (!taken.insert(t.name).second) fail(where + ".name", "'" + t.name + "' appears twice");
    t.robot = q["robot"] ? q["robot"].as<std::string>() : "";
    if (!defined["robot"].count(t.robot)) fail(where + ".robot", "no robot '" + t.robot + "' in robots");
    template_grid(t, q, where);
    template_grasps(t, q, where);
    template_settings(t, q, where);
    if (const YAML::Node runs = q["runs"]) {
      explicit_runs(t, runs, where);
    } else {
      for (const auto& object : t.objects)
        for (const auto& env : t.environments)
          for (const auto& grasp : t.grasps)
            for (const auto& variant : t.variants)
              for (int seed = 1; seed <= t.seeds; ++seed) t.runs.push_back({object, env, grasp.first, variant, seed});
    }
    m.queries.push_back(std::move(t));
  }
};

}  // namespace

BatchManifest read_batch_manifest(const fs::path& path) {
  ManifestReader r{{path.string(), path.parent_path()}, {}, {}};
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap()) r.fail("", "expected a map (name, robots, objects, environments, queries)");
  require_known_keys(root, {"name", "robots", "objects", "environments", "queries"}, r.file, "");
  r.m.path = path;
  try {
    r.m.name = root["name"] ? root["name"].as<std::string>() : path.stem().string();
    using W = const std::string&;
    r.each(root, "robots", [&](W name, const YAML::Node& n, W where) { r.robot(name, n, where); });
    r.each(root, "objects", [&](W name, const YAML::Node& n, W where) { r.objects(name, n, where); });
    r.each(root, "environments", [&](W name, const YAML::Node& n, W where) { r.environment(name, n, where); });
    const YAML::Node qs = root["queries"];
    if (qs && !qs.IsSequence()) r.fail("queries", "expected a list of query templates");
    std::set<std::string> template_names;
    for (std::size_t i = 0; qs && i < qs.size(); ++i) r.query_template(qs[i], i, template_names);
  } catch (const YAML::Exception& e) {
    throw Error(r.file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1),
                "malformed manifest: " + e.msg);
  }
  if (r.m.bakes.empty()) r.fail("", "nothing to bake (robots, objects, environments are all empty)");
  return std::move(r.m);
}

}  // namespace dmgplace::tools
