#include "dmgplace/tools/io/urdf_reader.hpp"
#include "dmgplace/tools/geometry/convex_hull.hpp"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/mesh_reader.hpp"
#include "dmgplace/tools/io/resource_path.hpp"

namespace dmgplace::tools {
namespace fs = std::filesystem;
namespace {

// urdfdom reports its parse errors only through console_bridge: collect them for the Error.
class CaptureLog : public console_bridge::OutputHandler {
 public:
  CaptureLog() { console_bridge::useOutputHandler(this); }
  ~CaptureLog() override { console_bridge::restorePreviousOutputHandler(); }
  CaptureLog(const CaptureLog&) = delete;
  CaptureLog& operator=(const CaptureLog&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors += (errors.empty() ? "" : "; ") + text;
  }
  std::string errors;
};

std::string quoted(const std::string& kind, const std::string& name) { return kind + " '" + name + "'"; }

Eigen::Isometry3d to_isometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() << p.position.x, p.position.y, p.position.z;
  Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  t.linear() = q.normalized().toRotationMatrix();
  return t;
}

Eigen::Vector3d to_vector(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string(), "", "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Shape convert_geometry(const urdf::Geometry& g, const std::string& file, const std::string& where,
                       const fs::path& base_dir, const UrdfOptions& options) {
  Shape s;
  auto positive = [&](double v, const std::string& what) {
    if (!std::isfinite(v) || v <= 0) throw Error(file, where, what + " must be positive and finite");
    return v;
  };
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& d = static_cast<const urdf::Box&>(g).dim;
      s.type = ShapeType::Box;
      s.size << positive(d.x, "box size x"), positive(d.y, "box size y"), positive(d.z, "box size z");
      return s;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      s.type = ShapeType::Cylinder;
      s.size << positive(c.radius, "cylinder radius"), positive(c.length, "cylinder length"), 0;
      return s;
    }
    case urdf::Geometry::SPHERE:
      s.type = ShapeType::Sphere;
      s.size << positive(static_cast<const urdf::Sphere&>(g).radius, "sphere radius"), 0, 0;
      return s;
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      std::vector<fs::path> tried;
      fs::path found;
      try {
        found = resolve_resource(m.filename, base_dir, options.package_paths, &tried);
      } catch (const Error& e) {
        throw Error(file, where, e.what());
      }
      if (found.empty())
        throw Error(file, where, "mesh '" + m.filename + "' not found (looked for " + describe_candidates(tried) + ")");
      MeshReadOptions ro;
      ro.axis_scale = to_vector(m.scale);
      s.type = ShapeType::Mesh;
      s.size = ro.axis_scale;
      try {
        s.mesh = read_mesh(found, ro);
      } catch (const Error& e) {
        throw Error(file, where, e.what());
      }
      s.hull = convex_hull_triangles(s.mesh);
      return s;
    }
  }
  throw Error(file, where, "unknown geometry type");
}

Link convert_link(const urdf::Link& l, const std::string& file, const fs::path& base_dir, const UrdfOptions& options) {
  Link link;
  link.name = l.name;
  if (options.skip_collision) return link;
  for (std::size_t i = 0; i < l.collision_array.size(); ++i) {
    const auto& c = l.collision_array[i];
    const std::string where = quoted("link", l.name) + " collision " + std::to_string(i);
    if (!c || !c->geometry) throw Error(file, where, "no geometry");
    Shape s = convert_geometry(*c->geometry, file, where, base_dir, options);
    s.origin = to_isometry(c->origin);
    link.collision.push_back(std::move(s));
  }
  return link;
}

Joint convert_joint(const urdf::Joint& j, const RobotModel& model, const std::string& file) {
  const std::string where = quoted("joint", j.name);
  Joint joint;
  joint.name = j.name;
  switch (j.type) {
    case urdf::Joint::FIXED:
      joint.type = JointType::Fixed;
      break;
    case urdf::Joint::REVOLUTE:
      joint.type = JointType::Revolute;
      break;
    case urdf::Joint::CONTINUOUS:
      joint.type = JointType::Continuous;
      break;
    case urdf::Joint::PRISMATIC:
      joint.type = JointType::Prismatic;
      break;
    case urdf::Joint::FLOATING:
      throw Error(file, where, "type floating is not supported (only fixed, revolute, continuous, prismatic)");
    case urdf::Joint::PLANAR:
      throw Error(file, where, "type planar is not supported (only fixed, revolute, continuous, prismatic)");
    default:
      throw Error(file, where, "unknown joint type");
  }
  joint.parent = model.link_index(j.parent_link_name);
  joint.child = model.link_index(j.child_link_name);
  joint.origin = to_isometry(j.parent_to_joint_origin_transform);

  const Eigen::Vector3d axis = to_vector(j.axis);
  if (joint.type == JointType::Fixed) {
    joint.axis = axis.allFinite() && axis.norm() > 1e-12 ? axis.normalized() : Eigen::Vector3d::UnitZ();
    return joint;
  }
  if (!axis.allFinite() || axis.norm() < 1e-12) throw Error(file, where + " axis", "axis must be a non-zero vector");
  joint.axis = axis.normalized();

  if (j.limits) {
    joint.velocity = j.limits->velocity;
    if (!std::isfinite(joint.velocity) || joint.velocity < 0)
      throw Error(file, where + " limit", "velocity must be finite and >= 0");
  }
  if (joint.type == JointType::Continuous) {
    joint.lower = -std::numbers::pi, joint.upper = std::numbers::pi;  // one turn: the joint wraps
    return joint;
  }
  if (!j.limits) throw Error(file, where, "needs a <limit> element");
  joint.lower = j.limits->lower, joint.upper = j.limits->upper;
  if (!std::isfinite(joint.lower) || !std::isfinite(joint.upper))
    throw Error(file, where + " limit", "lower and upper must be finite numbers");
  if (joint.lower > joint.upper)
    throw Error(file, where + " limit",
                "lower " + std::to_string(joint.lower) + " is above upper " + std::to_string(joint.upper));
  return joint;
}

// urdfdom links a joint's parent and child with shared_ptrs before it checks the tree, so a joint
// cycle (a link that is its own ancestor) leaked its links, and when urdfdom still found one root the
// cycle's links were dropped silently (found by fuzzing). Also rejects a link with two parent joints.
// "x y z" -> exactly `count` finite numbers, or an error naming the element and its line.
std::vector<double> parse_numbers(const char* text, std::size_t count, const std::string& file,
                                  const std::string& where) {
  std::vector<double> v;
  std::istringstream in(text ? text : "");
  std::string item;
  while (in >> item) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (end != item.c_str() + item.size() || !std::isfinite(x))
      throw Error(file, where, "'" + item + "' is not a finite number");
    v.push_back(x);
  }
  if (v.size() != count)
    throw Error(file, where,
                "expected " + std::to_string(count) + " numbers, got '" + std::string(text ? text : "") + "'");
  return v;
}

// urdfdom drops a <collision> whose origin or geometry it cannot parse (a NaN, a typo) and goes
// on, so a link silently lost its collision shapes. Every collision element is checked here, and
// its count per link is compared with what urdfdom kept. Also checks <inertial><mass>.
void check_link_elements(const tinyxml2::XMLElement& link, const std::string& file,
                         std::map<std::string, std::size_t>& collision_counts) {
  const char* name_attr = link.Attribute("name");
  const std::string name = name_attr ? name_attr : "";
  std::size_t index = 0;
  for (auto* c = link.FirstChildElement("collision"); c; c = c->NextSiblingElement("collision"), ++index) {
    const std::string where = quoted("link", name) + " collision " + std::to_string(index) + " (line " +
                              std::to_string(c->GetLineNum()) + ")";
    if (const auto* o = c->FirstChildElement("origin")) {
      if (o->Attribute("xyz")) {
        for (double x : parse_numbers(o->Attribute("xyz"), 3, file, where + " origin xyz"))
          if (std::abs(x) > kMaxGeometryExtent)
            throw Error(file, where + " origin xyz", "beyond " + std::to_string(int(kMaxGeometryExtent)) + " m");
      }
      if (o->Attribute("rpy")) parse_numbers(o->Attribute("rpy"), 3, file, where + " origin rpy");
    }
    const auto* g = c->FirstChildElement("geometry");
    const auto* shape = g ? g->FirstChildElement() : nullptr;
    if (!shape) throw Error(file, where, "no <geometry> with a shape");
    const std::string kind = shape->Name();
    const auto sizes = [&](const char* attr, std::size_t n) {
      const auto v = parse_numbers(shape->Attribute(attr), n, file, where + " " + kind + " " + attr);
      for (double x : v)
        if (!(x > 0) || x > kMaxGeometryExtent)
          throw Error(file, where + " " + kind + " " + attr,
                      "must be positive and at most " + std::to_string(int(kMaxGeometryExtent)) + " m");
    };
    if (kind == "box") sizes("size", 3);
    else if (kind == "cylinder") sizes("radius", 1), sizes("length", 1);
    else if (kind == "sphere") sizes("radius", 1);
    else if (kind == "mesh") {
      if (!shape->Attribute("filename")) throw Error(file, where + " mesh", "no filename");
      if (shape->Attribute("scale")) sizes("scale", 3);
    } else {
      throw Error(file, where, "unknown geometry <" + kind + "> (box, cylinder, sphere, mesh)");
    }
  }
  collision_counts[name] = index;
  if (const auto* inertial = link.FirstChildElement("inertial"))
    if (const auto* mass = inertial->FirstChildElement("mass")) {
      const double m = parse_numbers(mass->Attribute("value"), 1, file, quoted("link", name) + " inertial mass")[0];
      if (!(m > 0)) throw Error(file, quoted("link", name) + " inertial mass", "must be positive");
    }
}

void check_link_tree(const std::string& text, const std::string& file,
                     std::map<std::string, std::size_t>& collision_counts) {
  tinyxml2::XMLDocument doc;
  // urdfdom's own XML parser is more lenient: what tinyxml2 rejects is not checked here, so refuse it.
  if (doc.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS)
    throw Error(file, "", std::string("not valid XML: ") + (doc.ErrorStr() ? doc.ErrorStr() : "?"));
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) return;
  for (auto* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    check_link_elements(*l, file, collision_counts);
  std::map<std::string, std::string> parent_of;  // child link -> parent link
  for (auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const auto* p = j->FirstChildElement("parent");
    const auto* c = j->FirstChildElement("child");
    const char* parent = p ? p->Attribute("link") : nullptr;
    const char* child = c ? c->Attribute("link") : nullptr;
    if (!parent || !child) continue;  // urdfdom reports it
    if (!parent_of.emplace(child, parent).second)
      throw Error(file, quoted("link", child), "is the child of more than one joint");
  }
  std::set<std::string> below_root;  // links whose ancestors end at a root
  for (const auto& entry : parent_of) {
    std::vector<std::string> path;
    std::set<std::string> on_path;
    std::string link = entry.first;
    while (!below_root.count(link)) {
      if (!on_path.insert(link).second) throw Error(file, quoted("link", link), "is its own ancestor (joint cycle)");
      path.push_back(link);
      const auto up = parent_of.find(link);
      if (up == parent_of.end()) break;
      link = up->second;
    }
    below_root.insert(path.begin(), path.end());
  }
}

}  // namespace

RobotModel read_urdf(const fs::path& urdf, const UrdfOptions& options) {
  const std::string file = urdf.string();
  std::error_code ec;
  if (!fs::is_regular_file(urdf, ec)) throw Error(file, "", "file not found");
  const std::string text = read_text(urdf);

  std::map<std::string, std::size_t> collision_counts;
  check_link_tree(text, file, collision_counts);

  urdf::ModelInterfaceSharedPtr parsed;
  {
    CaptureLog log;
    try {
      parsed = urdf::parseURDF(text);
    } catch (const std::exception& e) {
      throw Error(file, "", std::string("not a valid URDF: ") + e.what());
    }
    if (!parsed)
      throw Error(file, "", "not a valid URDF: " + (log.errors.empty() ? "urdfdom rejected it" : log.errors));
  }
  const auto root = parsed->getRoot();
  if (!root) throw Error(file, "", "no root link");

  RobotModel model;
  model.name = parsed->getName();
  const fs::path base_dir = urdf.parent_path();
  // Depth-first from the root so every joint's parent link comes before its child link.
  std::vector<urdf::LinkConstSharedPtr> order, stack{root};
  std::set<const urdf::Link*> seen;
  while (!stack.empty()) {
    const auto link = stack.back();
    stack.pop_back();
    if (!seen.insert(link.get()).second) continue;
    order.push_back(link);
    std::vector<urdf::LinkSharedPtr> children = link->child_links;
    std::sort(children.begin(), children.end(), [](const auto& a, const auto& b) { return a->name > b->name; });
    for (const auto& c : children) stack.push_back(c);
  }
  for (const auto& [name, link] : parsed->links_)  // check_link_tree makes this a safety net
    if (!seen.count(link.get()))
      throw Error(file, quoted("link", name), "not connected to the root link '" + root->name + "' (joint cycle?)");
  for (const auto& l : order) {
    const auto expected = collision_counts.find(l->name);
    if (!options.skip_collision && expected != collision_counts.end() && expected->second != l->collision_array.size())
      throw Error(file, quoted("link", l->name),
                  "has " + std::to_string(expected->second) + " <collision> elements but only " +
                      std::to_string(l->collision_array.size()) + " could be read (a malformed origin or geometry)");
    model.links.push_back(convert_link(*l, file, base_dir, options));
  }
  for (const auto& l : order)
    if (l->parent_joint) model.joints.push_back(convert_joint(*l->parent_joint, model, file));

  // Mimic targets need every joint in place first.
  for (const auto& l : order) {
    const auto& j = l->parent_joint;
    if (!j || !j->mimic) continue;
    Joint& joint = model.joints[std::size_t(model.joint_index(j->name))];
    const std::string where = quoted("joint", j->name) + " mimic";
    joint.mimic = model.joint_index(j->mimic->joint_name);
    if (joint.mimic < 0) throw Error(file, where, "unknown joint '" + j->mimic->joint_name + "'");
    if (j->mimic->joint_name == j->name) throw Error(file, where, "a joint cannot mimic itself");
    joint.mimic_multiplier = j->mimic->multiplier;
    joint.mimic_offset = j->mimic->offset;
    if (!std::isfinite(joint.mimic_multiplier) || !std::isfinite(joint.mimic_offset))
      throw Error(file, where, "multiplier and offset must be finite");
  }
  return model;
}

void apply_srdf(RobotModel& model, const fs::path& srdf) {
  const std::string file = srdf.string();
  std::error_code ec;
  if (!fs::is_regular_file(srdf, ec)) throw Error(file, "", "file not found");
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(file.c_str()) != tinyxml2::XML_SUCCESS)
    throw Error(file, "", std::string("not valid XML: ") + (doc.ErrorStr() ? doc.ErrorStr() : "?"));
  const tinyxml2::XMLElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Name()) != "robot") throw Error(file, "", "the root element is not <robot>");

  for (auto* e = robot->FirstChildElement("disable_collisions"); e; e = e->NextSiblingElement("disable_collisions")) {
    const std::string where = "disable_collisions (line " + std::to_string(e->GetLineNum()) + ")";
    int idx[2];
    for (int k = 0; k < 2; ++k) {
      const char* attr = k == 0 ? "link1" : "link2";
      const char* name = e->Attribute(attr);
      if (!name) throw Error(file, where, std::string("missing attribute ") + attr);
      idx[k] = model.link_index(name);
      if (idx[k] < 0)
        throw Error(file, where,
                    std::string(attr) + ": unknown link '" + name + "' (not in robot '" + model.name + "')");
    }
    if (idx[0] == idx[1]) continue;  // a link never collides with itself anyway
    const std::pair<int, int> pair{std::min(idx[0], idx[1]), std::max(idx[0], idx[1])};
    if (std::find(model.allowed_pairs.begin(), model.allowed_pairs.end(), pair) == model.allowed_pairs.end())
      model.allowed_pairs.push_back(pair);
  }
}

void set_arm_chain(RobotModel& model, const std::string& base, const std::string& tip, const std::string& file) {
  const int b = model.link_index(base), t = model.link_index(tip);
  if (b < 0) throw Error(file, "arm base", "unknown link '" + base + "'");
  if (t < 0) throw Error(file, "arm tip", "unknown link '" + tip + "'");
  if (b == t) throw Error(file, "arm chain", "base and tip are the same link '" + base + "'");
  // Walk up from the tip through parent joints; a tree has at most links.size() steps.
  for (int link = t, steps = 0; steps <= int(model.links.size()); ++steps) {
    const auto up =
        std::find_if(model.joints.begin(), model.joints.end(), [&](const Joint& j) { return j.child == link; });
    if (up == model.joints.end()) break;
    link = up->parent;
    if (link == b) {
      model.arm_base = base;
      model.arm_tip = tip;
      return;
    }
  }
  throw Error(file, "arm chain", "tip '" + tip + "' does not descend from base '" + base + "'");
}

}  // namespace dmgplace::tools
