#include "dmgplace/formats/robot_artifact.hpp"

#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/shape_table.hpp"
#include "format_util.hpp"

namespace dmgplace::formats {
namespace {
constexpr int kJointReals = 15;            // origin(7) axis(3) lower upper velocity mimic_multiplier mimic_offset
constexpr long kMaxTableNodes = 1L << 22;  // per table: far more than any sensible joint step needs

// self_tables/indices [n, 6]: link_a link_b joint0 joint1 count0 count1
// self_tables/grid [n, 6]: lower0 step0 slope0 lower1 step1 slope1; self_tables/distance: all tables' nodes
void write_self_tables(H5Writer& w, const std::vector<SelfDistanceTable>& tables) {
  std::vector<std::int32_t> ints;
  std::vector<double> grid;
  std::vector<float> dist;
  for (const auto& t : tables) {
    ints.insert(ints.end(), {t.link_a, t.link_b, t.joints[0], t.joints[1], t.count[0], t.count[1]});
    grid.insert(grid.end(), {t.lower[0], t.step[0], t.slope[0], t.lower[1], t.step[1], t.slope[1]});
    dist.insert(dist.end(), t.distance.begin(), t.distance.end());
  }
  w.write("self_tables/indices", std::span<const std::int32_t>(ints), {tables.size(), 6});
  w.write("self_tables/grid", std::span<const double>(grid), {tables.size(), 6});
  w.write("self_tables/distance", std::span<const float>(dist), {dist.size()});
}

std::vector<SelfDistanceTable> read_self_tables(const H5Reader& r) {
  auto ints = r.read_i32("self_tables/indices", {-1, 6});
  auto grid = r.read_f64("self_tables/grid", {long(ints.rows()), 6});
  auto dist = r.read_f32("self_tables/distance", {-1});
  std::vector<SelfDistanceTable> out;
  std::size_t at = 0;
  for (std::size_t i = 0; i < ints.rows(); ++i) {
    SelfDistanceTable t;
    t.link_a = ints(i, 0);
    t.link_b = ints(i, 1);
    t.joints = {ints(i, 2), ints(i, 3)};
    t.count = {ints(i, 4), ints(i, 5)};
    for (int k = 0; k < 2; ++k) {
      t.lower[std::size_t(k)] = grid(i, std::size_t(3 * k));
      t.step[std::size_t(k)] = grid(i, std::size_t(3 * k + 1));
      t.slope[std::size_t(k)] = grid(i, std::size_t(3 * k + 2));
    }
    const std::string el = "self_tables row " + std::to_string(i);
    if (t.count[0] < 1 || t.count[1] < 1 || long(t.count[0]) * t.count[1] > kMaxTableNodes)
      throw Error(r.file(), "self_tables/indices", el + ": node count out of range");
    const std::size_t n = std::size_t(t.count[0]) * std::size_t(t.count[1]);
    if (at + n > dist.data.size())
      throw Error(r.file(), "self_tables/distance", el + ": fewer nodes than the tables declare");
    t.distance.assign(dist.data.begin() + long(at), dist.data.begin() + long(at + n));
    at += n;
    out.push_back(std::move(t));
  }
  if (at != dist.data.size()) throw Error(r.file(), "self_tables/distance", "more nodes than the tables declare");
  return out;
}
}  // namespace

void save_robot(RobotArtifact a, const std::filesystem::path& path) {
  a.header.schema = kRobotSchema;
  a.header.schema_version = kRobotSchemaVersion;
  const RobotModel& m = a.model;
  H5Writer w(path, a.header);
  std::vector<std::string> link_names, joint_names;
  std::vector<OwnedShape> shapes;
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    link_names.push_back(m.links[i].name);
    for (const auto& s : m.links[i].collision) shapes.push_back({int(i), s});
  }
  std::vector<std::int32_t> ints;
  std::vector<double> reals;
  for (const auto& j : m.joints) {
    joint_names.push_back(j.name);
    ints.insert(ints.end(), {int(j.type), j.parent, j.child, j.mimic});
    double o[7];
    pose_to_array(j.origin, o);
    reals.insert(reals.end(), o, o + 7);
    reals.insert(reals.end(), {j.axis.x(), j.axis.y(), j.axis.z(), j.lower, j.upper, j.velocity, j.mimic_multiplier,
                               j.mimic_offset});
  }
  std::vector<std::int32_t> pairs;
  for (auto [x, y] : m.allowed_pairs) pairs.insert(pairs.end(), {x, y});
  w.write_strings("links/names", link_names);
  write_shapes(w, "links/collision", shapes);
  w.write_strings("joints/names", joint_names);
  w.write("joints/indices", std::span<const std::int32_t>(ints), {m.joints.size(), 4});
  w.write("joints/values", std::span<const double>(reals), {m.joints.size(), std::size_t(kJointReals)});
  std::vector<double> accelerations;
  for (const auto& j : m.joints) accelerations.push_back(j.acceleration);
  w.write("joints/acceleration", std::span<const double>(accelerations), {m.joints.size()});
  w.write("allowed_pairs", std::span<const std::int32_t>(pairs), {m.allowed_pairs.size(), 2});
  std::vector<std::int32_t> sphere_link;
  std::vector<double> sphere_values;
  for (const auto& sp : a.spheres) {
    sphere_link.push_back(sp.link);
    sphere_values.insert(sphere_values.end(), {sp.center.x(), sp.center.y(), sp.center.z(), sp.radius});
  }
  w.write("links/sphere_link", std::span<const std::int32_t>(sphere_link), {a.spheres.size()});
  w.write("links/spheres", std::span<const double>(sphere_values), {a.spheres.size(), 4});
  write_self_tables(w, a.self_tables);
  w.attribute("", "robot_name", m.name);
  w.attribute("", "arm_base", m.arm_base);
  w.attribute("", "arm_tip", m.arm_tip);
  w.commit();
}

RobotArtifact load_robot(const std::filesystem::path& path) {
  RobotArtifact a = read_robot_unchecked(path);
  detail::require_sound(path.string(), check_robot(a));
  return a;
}

RobotArtifact read_robot_unchecked(const std::filesystem::path& path) {
  H5Reader r(path);
  r.require_schema(kRobotSchema, kRobotSchemaVersion);
  RobotArtifact a;
  a.header = r.header();
  a.header.source_file = r.file();
  RobotModel& m = a.model;
  m.name = r.attribute("", "robot_name").value_or("");
  m.arm_base = r.attribute("", "arm_base").value_or("");
  m.arm_tip = r.attribute("", "arm_tip").value_or("");
  auto link_names = r.read_strings("links/names");
  for (auto& n : link_names) m.links.push_back({n, {}});
  if (!r.has("links/collision/hull_ranges"))
    throw Error(r.file(), "links/collision/hull_ranges", "missing (convex hulls of mesh shapes)");
  for (auto& os : read_shapes(r, "links/collision")) {
    if (os.owner < 0 || std::size_t(os.owner) >= m.links.size())
      throw Error(r.file(), "links/collision/owner", "link index out of range");
    m.links[std::size_t(os.owner)].collision.push_back(std::move(os.shape));
  }
  auto joint_names = r.read_strings("joints/names");
  const long nj = long(joint_names.size());
  auto ints = r.read_i32("joints/indices", {nj, 4});
  auto reals = r.read_f64("joints/values", {nj, kJointReals});
  auto accelerations = r.read_f64("joints/acceleration", {nj});
  for (long i = 0; i < nj; ++i) {
    Joint j;
    j.name = joint_names[std::size_t(i)];
    if (ints(i, 0) < 0 || ints(i, 0) > 3)
      throw Error(r.file(), "joints/indices", "unknown joint type in row " + std::to_string(i));
    j.type = JointType(ints(i, 0));
    j.parent = ints(i, 1);
    j.child = ints(i, 2);
    j.mimic = ints(i, 3);
    const double* v = &reals.data[std::size_t(i) * kJointReals];
    j.origin = pose_from_array(v, r.file(), "joints/values row " + std::to_string(i) + " origin");
    j.axis = Eigen::Vector3d(v[7], v[8], v[9]);
    j.lower = v[10];
    j.upper = v[11];
    j.velocity = v[12];
    j.mimic_multiplier = v[13];
    j.mimic_offset = v[14];
    j.acceleration = accelerations.data[std::size_t(i)];
    m.joints.push_back(j);
  }
  auto sphere_link = r.read_i32("links/sphere_link", {-1});
  auto spheres = r.read_f64("links/spheres", {long(sphere_link.rows()), 4});
  for (std::size_t i = 0; i < sphere_link.rows(); ++i)
    a.spheres.push_back(
        {sphere_link.data[i], Eigen::Vector3d(spheres(i, 0), spheres(i, 1), spheres(i, 2)), spheres(i, 3)});
  auto pairs = r.read_i32("allowed_pairs", {-1, 2});
  for (std::size_t i = 0; i < pairs.rows(); ++i) m.allowed_pairs.emplace_back(pairs(i, 0), pairs(i, 1));
  a.self_tables = read_self_tables(r);
  return a;
}

namespace {
// One joint's indices, pose, axis, limits and mimic; records it as its child's parent joint.
void check_joint(const RobotModel& m, std::size_t i, std::vector<int>& parent_joint, std::vector<std::string>& p) {
  const int nl = int(m.links.size());
  const Joint& j = m.joints[i];
  const std::string el = "joints[" + std::to_string(i) + "] '" + j.name + "'";
  if (j.parent < 0 || j.parent >= nl || j.child < 0 || j.child >= nl) {
    p.push_back(el + ": link index out of range");
    return;
  }
  if (parent_joint[std::size_t(j.child)] >= 0)
    p.push_back(el + ": link '" + m.links[std::size_t(j.child)].name + "' has two parent joints");
  parent_joint[std::size_t(j.child)] = int(i);
  if (!j.origin.matrix().allFinite() || !detail::is_rotation(j.origin.linear()))
    p.push_back(el + ": origin not a finite rigid pose");
  if (j.type != JointType::Fixed && !(std::abs(j.axis.norm() - 1) <= 1e-6))
    p.push_back(el + ": axis is not a finite unit vector");
  if (j.type == JointType::Revolute || j.type == JointType::Prismatic) {
    if (!std::isfinite(j.lower) || !std::isfinite(j.upper) || j.lower > j.upper)
      p.push_back(el + ": joint limits invalid (lower > upper or not finite)");
  }
  if (!std::isfinite(j.velocity) || j.velocity < 0) p.push_back(el + ": velocity limit must be finite and >= 0");
  if (!std::isfinite(j.acceleration) || j.acceleration < 0)
    p.push_back(el + ": acceleration limit must be finite and >= 0");
  if (j.mimic < -1 || j.mimic >= int(m.joints.size()) || j.mimic == int(i))
    p.push_back(el + ": mimic joint index invalid");
  if (j.mimic >= 0 && (!std::isfinite(j.mimic_multiplier) || !std::isfinite(j.mimic_offset)))
    p.push_back(el + ": mimic multiplier and offset must be finite");
}

// Mimic chains end at an independent joint, the links form one tree (one root, no loop).
void check_tree(const RobotModel& m, const std::vector<int>& parent_joint, std::vector<std::string>& p) {
  const int nl = int(m.links.size());
  // A mimic chain must end at an independent joint: a loop would make forward kinematics recurse.
  for (std::size_t i = 0; i < m.joints.size(); ++i) {
    int cur = int(i), steps = 0;
    while (cur >= 0 && cur < int(m.joints.size()) && m.joints[std::size_t(cur)].mimic >= 0 &&
           steps <= int(m.joints.size())) {
      cur = m.joints[std::size_t(cur)].mimic;
      ++steps;
    }
    if (steps > int(m.joints.size())) {
      p.push_back("joints[" + std::to_string(i) + "] '" + m.joints[i].name + "': mimic loop");
      break;
    }
  }
  int roots = 0;
  for (int l = 0; l < nl; ++l) roots += parent_joint[std::size_t(l)] < 0;
  if (nl > 0 && roots != 1)
    p.push_back("links: the kinematic tree must have exactly one root, found " + std::to_string(roots));
  // Cycle check: walking up from every link must end at the root within nl steps.
  for (int l = 0; l < nl && p.empty(); ++l) {
    int cur = l, steps = 0;
    while (parent_joint[std::size_t(cur)] >= 0 && steps <= nl) {
      cur = m.joints[std::size_t(parent_joint[std::size_t(cur)])].parent;
      ++steps;
    }
    if (steps > nl) p.push_back("joints: kinematic loop through link '" + m.links[std::size_t(l)].name + "'");
  }
}

// Every sphere on a link with a positive finite radius, and every link with geometry covered.
void check_spheres(const RobotArtifact& a, std::vector<std::string>& p) {
  const RobotModel& m = a.model;
  const int nl = int(m.links.size());
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    const auto& sp = a.spheres[i];
    if (sp.link < 0 || sp.link >= nl || !sp.center.allFinite() || !(sp.radius > 0) || !std::isfinite(sp.radius))
      p.push_back("links/spheres[" + std::to_string(i) + "]: link out of range or radius not positive and finite");
  }
  for (int l = 0; l < nl; ++l) {
    if (m.links[std::size_t(l)].collision.empty()) continue;
    bool covered = false;
    for (const auto& sp : a.spheres) covered |= sp.link == l;
    if (!covered)
      p.push_back("links/spheres: link '" + m.links[std::size_t(l)].name + "' has collision geometry but no spheres");
  }
}

void check_table(const RobotModel& m, const SelfDistanceTable& t, std::size_t i, std::vector<std::string>& p) {
  const int nl = int(m.links.size()), nj = int(m.joints.size());
  const std::string el = "self_tables[" + std::to_string(i) + "]";
  if (t.link_a < 0 || t.link_b < 0 || t.link_a >= nl || t.link_b >= nl || t.link_a == t.link_b)
    p.push_back(el + ": link pair out of range");
  if (t.joints[0] < 0 || t.joints[0] >= nj || t.joints[1] < -1 || t.joints[1] >= nj || t.joints[0] == t.joints[1])
    p.push_back(el + ": joint index out of range");
  if (t.joints[1] < 0 && t.count[1] != 1) p.push_back(el + ": 1-D table with more than one column");
  bool grid_ok = true;
  for (int k = 0; k < 2; ++k)
    grid_ok &= std::isfinite(t.lower[std::size_t(k)]) && t.step[std::size_t(k)] > 0 &&
               std::isfinite(t.step[std::size_t(k)]) && t.slope[std::size_t(k)] >= 0 &&
               std::isfinite(t.slope[std::size_t(k)]);
  if (!grid_ok) p.push_back(el + ": grid lower/step/slope not finite or step not positive or slope negative");
  if (t.distance.size() != std::size_t(std::max(t.count[0], 0)) * std::size_t(std::max(t.count[1], 0)))
    p.push_back(el + ": distance count does not match the grid");
  for (float d : t.distance)
    if (!(d >= 0) || !std::isfinite(d)) {
      p.push_back(el + ": distance negative or not finite");
      break;
    }
}

// The planning chain's ends are links, the tip below the base (asked only of an otherwise sound tree).
void check_chain(const RobotModel& m, const std::vector<int>& parent_joint, std::vector<std::string>& p) {
  const int base = m.link_index(m.arm_base), tip = m.link_index(m.arm_tip);
  if (base < 0 || tip < 0) {
    p.push_back("arm chain: base '" + m.arm_base + "' or tip '" + m.arm_tip + "' is not a link");
  } else if (p.empty()) {
    int cur = tip;
    while (cur != base && parent_joint[std::size_t(cur)] >= 0)
      cur = m.joints[std::size_t(parent_joint[std::size_t(cur)])].parent;
    if (cur != base) p.push_back("arm chain: tip '" + m.arm_tip + "' does not descend from base '" + m.arm_base + "'");
  }
}
}  // namespace

std::vector<std::string> check_robot(const RobotArtifact& a) {
  const RobotModel& m = a.model;
  std::vector<std::string> p;
  const int nl = int(m.links.size());
  if (nl == 0) p.push_back("links: robot has no links");
  std::vector<int> parent_joint(std::size_t(std::max(nl, 0)), -1);
  for (std::size_t i = 0; i < m.joints.size(); ++i) check_joint(m, i, parent_joint, p);
  check_tree(m, parent_joint, p);
  std::vector<OwnedShape> shapes;
  for (std::size_t i = 0; i < m.links.size(); ++i)
    for (const auto& s : m.links[i].collision) shapes.push_back({int(i), s});
  detail::append(p, check_shapes(shapes, nl, "links/collision"));
  for (auto [x, y] : m.allowed_pairs)
    if (x < 0 || y < 0 || x >= nl || y >= nl || x == y)
      p.push_back("allowed_pairs: invalid pair (" + std::to_string(x) + ", " + std::to_string(y) + ")");
  check_spheres(a, p);
  for (std::size_t i = 0; i < a.self_tables.size(); ++i) check_table(m, a.self_tables[i], i, p);
  check_chain(m, parent_joint, p);
  return p;
}

Summary summarize_robot(const RobotArtifact& a) {
  const RobotModel& m = a.model;
  int moving = 0, shapes = 0, meshes = 0, hulls = 0;
  for (const auto& j : m.joints) moving += j.type != JointType::Fixed && j.mimic < 0;
  for (const auto& l : m.links) {
    shapes += int(l.collision.size());
    for (const auto& c : l.collision) {
      meshes += c.type == ShapeType::Mesh;
      hulls += c.type == ShapeType::Mesh && c.hull.rows() > 0;
    }
  }
  Summary s;
  s.emplace_back("robot", m.name);
  s.emplace_back("links", std::to_string(m.links.size()));
  s.emplace_back("joints", std::to_string(m.joints.size()));
  s.emplace_back("independent_joints", std::to_string(moving));
  s.emplace_back("collision_shapes", std::to_string(shapes));
  // Meshes with a hull: the exact layer's gaps (certificates near the scene) need every one.
  s.emplace_back("mesh_hulls", std::to_string(hulls) + " of " + std::to_string(meshes) + " meshes");
  s.emplace_back("allowed_pairs", std::to_string(m.allowed_pairs.size()));
  s.emplace_back("spheres", std::to_string(a.spheres.size()));
  std::string tables = std::to_string(a.self_tables.size());
  const auto name = [&](int l) {
    return l >= 0 && std::size_t(l) < m.links.size() ? m.links[std::size_t(l)].name : "?";
  };
  for (std::size_t i = 0; i < a.self_tables.size(); ++i)
    tables += (i == 0 ? " (" : ", ") + name(a.self_tables[i].link_a) + "/" + name(a.self_tables[i].link_b) +
              (i + 1 == a.self_tables.size() ? ")" : "");
  s.emplace_back("self_distance_tables", tables);
  s.emplace_back("arm_chain", m.arm_base + " -> " + m.arm_tip);
  return s;
}

}  // namespace dmgplace::formats
