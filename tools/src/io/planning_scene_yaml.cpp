// read_planning_scene_yaml (declared in scene_reader.hpp): MoveIt PlanningScene YAML with yaml-cpp.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/mesh_check.hpp"
#include "dmgplace/tools/io/resource_path.hpp"
#include "dmgplace/tools/io/scene_reader.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;
namespace {

// Where we are, for error messages: the file and "object 'ID' field[i]".
struct Ctx {
  std::string file;
  std::string where;
  Ctx operator/(const std::string& field) const {
    const char sep = where.empty() ? '\0' : where.back() == '\'' ? ' ' : '.';  // "object 'id' meshes[0].resource"
    return {file, sep ? where + sep + field : field};
  }
  Ctx at(std::size_t i) const { return {file, where + "[" + std::to_string(i) + "]"}; }
  [[noreturn]] void fail(const std::string& reason) const { throw Error(file, where, reason); }
};

double number(const YAML::Node& n, const Ctx& c) {
  double v = 0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) c.fail("expected a number");
  if (!std::isfinite(v)) c.fail("number is not finite");
  return v;
}

// A sequence of `names.size()` numbers, or a map with those keys ({x: .., y: .., z: ..}).
Eigen::VectorXd components(const YAML::Node& n, const Ctx& c, const std::string& names) {
  Eigen::VectorXd v(Eigen::Index(names.size()));
  if (n.IsSequence()) {
    if (n.size() != names.size())
      c.fail("expected " + std::to_string(names.size()) + " numbers [" + names + "], got " + std::to_string(n.size()));
    for (std::size_t i = 0; i < names.size(); ++i) v(Eigen::Index(i)) = number(n[i], c.at(i));
  } else if (n.IsMap()) {
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string key(1, names[i]);
      if (!n[key]) c.fail("missing component " + key);
      v(Eigen::Index(i)) = number(n[key], c / key);
    }
  } else {
    c.fail("expected a list of " + std::to_string(names.size()) + " numbers [" + names + "]");
  }
  return v;
}

Eigen::Quaterniond quaternion(const YAML::Node& n, const Ctx& c) {
  const Eigen::VectorXd v = components(n, c, "xyzw");
  if (v.isZero()) return Eigen::Quaterniond::Identity();  // MoveIt reads an all-zero quaternion as identity
  if (std::abs(v.norm() - 1.0) > 1e-2)
    c.fail("quaternion [x, y, z, w] has norm " + std::to_string(v.norm()) + ", not 1");
  return Eigen::Quaterniond(v(3), v(0), v(1), v(2)).normalized();
}

Eigen::Isometry3d transform(const YAML::Node& n, const Ctx& c, const char* pos_key, const char* rot_key) {
  if (!n.IsMap()) c.fail(std::string("expected a map with ") + pos_key + " and " + rot_key);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (n[pos_key]) t.translation() = components(n[pos_key], c / pos_key, "xyz");
  if (n[rot_key]) t.linear() = quaternion(n[rot_key], c / rot_key).toRotationMatrix();
  return t;
}

Eigen::Isometry3d pose(const YAML::Node& n, const Ctx& c) { return transform(n, c, "position", "orientation"); }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return s;
}

Shape primitive(const YAML::Node& n, const Ctx& c) {
  if (!n.IsMap()) c.fail("expected a map with type and dimensions");
  if (!n["type"] || !n["type"].IsScalar()) (c / "type").fail("missing primitive type");
  // Text names or shape_msgs/SolidPrimitive numbers (1 box, 2 sphere, 3 cylinder, 4 cone).
  const std::string type = lower(n["type"].Scalar());
  Shape s;
  if (type == "box" || type == "1") {
    s.type = ShapeType::Box;
  } else if (type == "sphere" || type == "2") {
    s.type = ShapeType::Sphere;
  } else if (type == "cylinder" || type == "3") {
    s.type = ShapeType::Cylinder;
  } else {
    (c / "type").fail("unsupported primitive type '" + n["type"].Scalar() + "' (box, cylinder, sphere)");
  }
  const std::size_t count = s.type == ShapeType::Box ? 3 : s.type == ShapeType::Cylinder ? 2 : 1;

  const Ctx dc = c / "dimensions";
  if (!n["dimensions"] || !n["dimensions"].IsSequence()) dc.fail("missing dimensions list");
  const YAML::Node d = n["dimensions"];
  if (d.size() != count)
    dc.fail(type + " needs " + std::to_string(count) + " dimensions" +
            (s.type == ShapeType::Cylinder ? " [height, radius]"
             : s.type == ShapeType::Box    ? " [x, y, z]"
                                           : " [radius]") +
            ", got " + std::to_string(d.size()));
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    v(Eigen::Index(i)) = number(d[i], dc.at(i));
    if (v(Eigen::Index(i)) <= 0) dc.at(i).fail("dimension must be positive");
  }
  s.size = s.type == ShapeType::Cylinder ? Eigen::Vector3d(v(1), v(0), 0) : v;  // (radius, length, 0)
  return s;
}

TriMesh inline_mesh(const YAML::Node& n, const Ctx& c) {
  const YAML::Node vs = n["vertices"], ts = n["triangles"];
  if (!vs || !vs.IsSequence()) (c / "vertices").fail("expected a list of [x, y, z]");
  if (!ts || !ts.IsSequence()) (c / "triangles").fail("expected a list of [i, j, k]");
  TriMesh m;
  m.vertices.resize(Eigen::Index(vs.size()), 3);
  for (std::size_t i = 0; i < vs.size(); ++i)
    m.vertices.row(Eigen::Index(i)) = components(vs[i], (c / "vertices").at(i), "xyz").transpose();
  m.triangles.resize(Eigen::Index(ts.size()), 3);
  for (std::size_t i = 0; i < ts.size(); ++i) {
    const Ctx tc = (c / "triangles").at(i);
    // shape_msgs/MeshTriangle writes {vertex_indices: [i, j, k]}.
    const YAML::Node t = ts[i].IsMap() ? ts[i]["vertex_indices"] : ts[i];
    if (!t || !t.IsSequence() || t.size() != 3) tc.fail("expected three vertex indices");
    for (std::size_t j = 0; j < 3; ++j) {
      int idx = 0;
      if (!t[j].IsScalar() || !YAML::convert<int>::decode(t[j], idx)) tc.at(j).fail("expected an integer index");
      m.triangles(Eigen::Index(i), Eigen::Index(j)) = idx;
    }
  }
  MeshReport report;
  return clean_mesh(m, c.file + ": " + c.where, report);  // its errors then name file and field
}

Shape mesh(const YAML::Node& n, const Ctx& c, const fs::path& base_dir, const std::vector<fs::path>& packages) {
  if (!n.IsMap()) c.fail("expected a map with resource, or vertices and triangles");
  Shape s;
  s.type = ShapeType::Mesh;
  s.size = Eigen::Vector3d::Ones();
  if (n["resource"]) {
    const Ctx rc = c / "resource";
    if (!n["resource"].IsScalar() || n["resource"].Scalar().empty()) rc.fail("expected a file name");
    std::vector<fs::path> tried;
    fs::path found;
    try {
      found = resolve_resource(n["resource"].Scalar(), base_dir, packages, &tried);
    } catch (const Error& e) {
      rc.fail(e.what());
    }
    if (found.empty())
      rc.fail("mesh '" + n["resource"].Scalar() + "' not found (looked for " + describe_candidates(tried) + ")");
    try {
      s.mesh = read_mesh(found);
    } catch (const Error& e) {
      rc.fail(e.what());
    }
  } else if (n["vertices"] || n["triangles"]) {
    s.mesh = inline_mesh(n, c);
  } else {
    c.fail("a mesh needs a resource, or vertices and triangles");
  }
  return s;
}

// Shapes of one kind ("primitives" / "meshes") with their poses, placed by `placement`.
template <class Read>
void read_shapes(const YAML::Node& obj, const Ctx& c, const char* key, const char* pose_key,
                 const Eigen::Isometry3d& placement, std::vector<Shape>& out, Read read) {
  if (!obj[key]) return;
  if (!obj[key].IsSequence()) (c / key).fail("expected a list");
  const YAML::Node shapes = obj[key], poses = obj[pose_key];
  if (!poses || !poses.IsSequence() || poses.size() != shapes.size())
    (c / pose_key).fail("needs one pose per entry of " + std::string(key) + " (" + std::to_string(shapes.size()) + ")");
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    Shape s = read(shapes[i], (c / key).at(i));
    s.origin = placement * pose(poses[i], (c / pose_key).at(i));
    out.push_back(std::move(s));
  }
}

std::map<std::string, Eigen::Isometry3d> fixed_frames(const YAML::Node& root, const std::string& file) {
  std::map<std::string, Eigen::Isometry3d> frames;
  const YAML::Node list = root["fixed_frame_transforms"];
  if (!list) return frames;
  const Ctx c{file, "fixed_frame_transforms"};
  if (!list.IsSequence()) c.fail("expected a list");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Ctx ic = c.at(i);
    const YAML::Node t = list[i];
    if (!t.IsMap() || !t["child_frame_id"] || !t["child_frame_id"].IsScalar()) ic.fail("missing child_frame_id");
    if (!t["transform"]) (ic / "transform").fail("missing transform");
    frames[t["child_frame_id"].Scalar()] = transform(t["transform"], ic / "transform", "translation", "rotation");
  }
  return frames;
}

}  // namespace

namespace {

Scene read_scene(const YAML::Node& root, const fs::path& yaml, const std::vector<fs::path>& package_paths) {
  const std::string file = yaml.string();
  if (!root.IsMap()) throw Error(file, "", "expected a PlanningScene map at the top level");
  if (!root["world"] || !root["world"].IsMap()) throw Error(file, "world", "missing world map (not a PlanningScene?)");
  const auto frames = fixed_frames(root, file);

  Scene scene;
  const YAML::Node objects = root["world"]["collision_objects"];
  if (!objects) return scene;  // an empty world is a valid scene
  if (!objects.IsSequence()) throw Error(file, "world.collision_objects", "expected a list");
  const fs::path base_dir = yaml.parent_path();
  std::set<std::string> ids;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const YAML::Node obj = objects[i];
    const Ctx ic{file, "collision_objects[" + std::to_string(i) + "]"};
    if (!obj.IsMap()) ic.fail("expected a map");
    if (!obj["id"] || !obj["id"].IsScalar() || obj["id"].Scalar().empty()) (ic / "id").fail("missing object id");
    const std::string id = obj["id"].Scalar();
    const Ctx c{file, "object '" + id + "'"};
    if (!ids.insert(id).second) c.fail("duplicate object id");
    if (obj["operation"]) {
      const std::string op = obj["operation"].IsScalar() ? lower(obj["operation"].Scalar()) : "?";
      if (op != "0" && op != "add") (c / "operation").fail("only add (0) belongs in a scene file, got '" + op + "'");
    }
    if (obj["planes"] && obj["planes"].size() > 0) (c / "planes").fail("planes are not supported");

    Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
    const YAML::Node header = obj["header"];
    if (header && header.IsMap() && header["frame_id"] && header["frame_id"].IsScalar()) {
      const auto f = frames.find(header["frame_id"].Scalar());
      if (f != frames.end()) placement = f->second;
    }
    if (obj["pose"]) placement = placement * pose(obj["pose"], c / "pose");

    SceneObject so;
    so.name = id;
    read_shapes(obj, c, "primitives", "primitive_poses", placement, so.shapes, primitive);
    read_shapes(obj, c, "meshes", "mesh_poses", placement, so.shapes,
                [&](const YAML::Node& n, const Ctx& mc) { return mesh(n, mc, base_dir, package_paths); });
    if (so.shapes.empty()) c.fail("no primitives or meshes");
    scene.objects.push_back(std::move(so));
  }
  return scene;
}

}  // namespace

Scene read_planning_scene_yaml(const fs::path& yaml, const std::vector<fs::path>& package_paths) {
  const std::string file = yaml.string();
  std::error_code ec;
  if (!fs::is_regular_file(yaml, ec)) throw Error(file, "", "file not found");
  try {
    return read_scene(YAML::LoadFile(file), yaml, package_paths);
  } catch (const YAML::Exception& e) {  // syntax errors, and any node access the checks above missed
    throw Error(file, e.mark.is_null() ? "" : "line " + std::to_string(e.mark.line + 1), "not valid YAML: " + e.msg);
  }
}

}  // namespace dmgplace::tools
