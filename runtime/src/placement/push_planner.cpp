#include "dmgplace/runtime/placement/push_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/runtime/motion/free_motion.hpp"
#include "dmgplace/runtime/motion/segment_check.hpp"
#include "dmgplace/runtime/placement/push_geometry.hpp"
#include "dmgplace/runtime/robot/ik.hpp"

namespace dmgplace::runtime {
namespace {
constexpr int kContacts = 8;             // candidate contacts tried per action
constexpr int kSpins = 4;                // tool turns about its axis tried per tool axis
constexpr double kTilt = 0.5;            // rad: the tool's axis may lean this far from the push (four ways)
constexpr double kContactSpacing = 0.1;  // of the object's size, between candidate contacts
constexpr double kMaxJointStep = 0.25;   // rad: one Cartesian step may move a joint this far (else the IK jumped)
constexpr double kMaxTurnStep = 0.05;    // rad of the object's turn per Cartesian step

// The pusher's links that may touch the object while pushing: those rigid with the TCP (no chain
// joint between them and the tip) that have collision geometry, less the link the last chain joint
// drives (a wrist) when another one has geometry (the tool proper).
std::vector<int> rigid_tool_links(const Kinematics& kin) {
  const RobotModel& m = kin.model();
  std::vector<int> parent_joint(m.links.size(), -1);
  for (std::size_t j = 0; j < m.joints.size(); ++j) parent_joint[std::size_t(m.joints[j].child)] = int(j);
  // Walk up from the tip to the first chain joint: that joint's child is the wrist.
  int wrist = kin.tip_link();
  for (int l = kin.tip_link(); parent_joint[std::size_t(l)] >= 0;) {
    const int j = parent_joint[std::size_t(l)];
    if (kin.chain_slot(j) >= 0) {
      wrist = l;
      break;
    }
    l = m.joints[std::size_t(j)].parent;
  }
  // Rigid with the wrist: the wrist and every link below it through non-chain joints.
  std::vector<int> rigid{wrist};
  for (std::size_t k = 0; k < rigid.size(); ++k)
    for (std::size_t j = 0; j < m.joints.size(); ++j)
      if (m.joints[j].parent == rigid[k] && kin.chain_slot(int(j)) < 0) rigid.push_back(m.joints[j].child);
  std::vector<int> out;
  for (int l : rigid)
    if (l != wrist && !m.links[std::size_t(l)].collision.empty()) out.push_back(l);
  if (out.empty() && !m.links[std::size_t(wrist)].collision.empty()) out.push_back(wrist);
  return out;
}

// The tool frames tried at a contact: at `point`, z along `z` and leaning from it by kTilt four
// ways, each turned kSpins ways about its own z. A round tool tip pushes the same leaning a little.
std::vector<Eigen::Isometry3d> tool_frames(const Eigen::Vector3d& point, const Eigen::Vector3d& z) {
  const Eigen::Vector3d helper = std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x0 = (helper - helper.dot(z) * z).normalized();
  Eigen::Matrix3d R;
  R.col(0) = x0;
  R.col(1) = z.cross(x0);
  R.col(2) = z;
  std::vector<Eigen::Isometry3d> out;
  for (int lean = 0; lean <= 4; ++lean) {
    const double az = M_PI / 2 * lean;
    const Eigen::Matrix3d tilt =
        lean == 0 ? Eigen::Matrix3d::Identity()
                  : Eigen::AngleAxisd(kTilt, Eigen::Vector3d(std::cos(az), std::sin(az), 0)).toRotationMatrix();
    for (int k = 0; k < kSpins; ++k) {
      Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
      f.linear() = R * tilt * Eigen::AngleAxisd(2 * M_PI * k / kSpins, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      f.translation() = point;
      out.push_back(f);
    }
  }
  return out;
}

const Eigen::Map<const Eigen::VectorXd> vec(const std::vector<double>& v) { return {v.data(), Eigen::Index(v.size())}; }
}  // namespace

PushPlanner::PushPlanner(const PlacementWorld& world, const PusherSpec& spec, const Eigen::VectorXd& q0,
                         double resolution, std::uint64_t seed, const std::string& source)
    : world_(world), spec_(spec), q0_(q0), resolution_(resolution), seed_(seed) {
  const Kinematics& arm = world.kinematics();
  const RobotModel& m = arm.model();
  const std::string el = "pusher.arm";
  for (const std::string& link : {spec.base, spec.tip})
    if (m.link_index(link) < 0) throw Error(source, el, "no link '" + link + "' in robot '" + m.name + "'");
  const std::string arm_base = m.links[std::size_t(arm.base_link())].name;
  std::unique_ptr<Kinematics> own;
  try {
    kin_ = std::make_unique<Kinematics>(m, arm_base, spec.tip);
    own = std::make_unique<Kinematics>(m, spec.base, spec.tip);
  } catch (const Error& e) {
    throw Error(source, el,
                "'" + spec.base + ":" + spec.tip + "' is not a chain below the grasping arm's base '" + arm_base +
                    "': " + e.what());
  }
  if (own->dof() != kin_->dof())
    throw Error(source, el,
                "joints move between the grasping arm's base '" + arm_base + "' and the pusher's base '" + spec.base +
                    "': the pusher's base must be rigid with it");
  if (kin_->dof() == 0) throw Error(source, el, "the chain '" + spec.base + ":" + spec.tip + "' has no moving joint");
  for (const auto& name : kin_->joint_names())
    if (arm.chain_slot(m.joint_index(name)) >= 0)
      throw Error(source, el,
                  "the chain shares joint '" + name + "' with the grasping arm: the pusher must be another arm");
  if (!spec.tcp.matrix().allFinite()) throw Error(source, "pusher.tcp", "not finite (NaN or infinity)");
  auto positive = [&](double v, double hi, const char* name) {
    if (!(std::isfinite(v) && v > 0 && v <= hi))
      throw Error(source, std::string("pusher.") + name,
                  "must be in (0, " + number_text(hi) + "], got " + number_text(v));
  };
  positive(spec.standoff, 0.5, "standoff");
  positive(spec.step, 0.05, "step");
  positive(spec.plan_time, 60, "plan_time");
  if (spec.plan_iterations < 1 || spec.plan_iterations > 1000000)
    throw Error(source, "pusher.plan_iterations", "must be in [1, 1e+06], got " + std::to_string(spec.plan_iterations));
  // Every other joint as the world has it at q0: the grasping arm there, the fingers as set.
  for (std::size_t j = 0; j < m.joints.size(); ++j) {
    const Joint& jt = m.joints[j];
    if (jt.type == JointType::Fixed || jt.mimic >= 0 || kin_->chain_slot(int(j)) >= 0) continue;
    kin_->set_joint_value(jt.name, arm.joint_value(int(j), q0));
  }
  start_.resize(kin_->dof());
  for (int i = 0; i < kin_->dof(); ++i)
    start_[i] = arm.joint_value(m.joint_index(kin_->joint_names()[std::size_t(i)]), q0);
  if (!kin_->within_limits(start_, 1e-6))
    throw Error(source, "pusher",
                "the pusher's joints are outside its limits where the world holds them; name them in start");
  exact_ = std::make_unique<ExactChecker>(*kin_, world.scene());
  const ExactCheck at_start = exact_->check(start_);
  if (!at_start.free())
    throw Error(source, "pusher", "the pusher's start configuration is in collision: " + at_start.contact);
  tool_ = rigid_tool_links(*kin_);
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < world.object().mesh.vertices.rows(); ++i)
    box.extend(Eigen::Vector3d(world.object().mesh.vertices.row(i).transpose()));
  contact_spacing_ = kContactSpacing * box.diagonal().norm();
  if (tool_.empty())
    throw Error(source, el, "no link with collision geometry is rigid with the pusher's tip: nothing to push with");
}

PushPlanner::~PushPlanner() = default;

long PushPlanner::planned() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return planned_;
}

double PushPlanner::seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return seconds_;
}

std::optional<std::vector<PushPlan>> PushPlanner::plan(const std::vector<InHandAction>& actions,
                                                       const TimingOptions& timing) {
  std::vector<PushPlan> out;
  for (std::size_t i = 0; i < actions.size(); ++i) {
    const std::pair<int, int> key{actions[i].from_state, actions[i].to_state};
    std::optional<PushPlan> p;
    bool cached = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto it = cache_.find(key);
      if (it != cache_.end()) p = it->second, cached = true;
    }
    if (!cached) {
      const auto t0 = std::chrono::steady_clock::now();
      p = plan_action(actions[i]);
      if (p) p->trajectory = time_arm_path(*kin_, p->path, TimingOptions{});
      const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(mutex_);
      cache_[key] = p;
      ++planned_;
      seconds_ += took;
    }
    if (!p) return std::nullopt;
    p->action = int(i);
    if (timing.velocity_scaling != 1 || timing.acceleration_scaling != 1)
      p->trajectory = time_arm_path(*kin_, p->path, timing);
    out.push_back(std::move(*p));
  }
  return out;
}

// A TCP pose on the push and what the pusher may touch there: nothing (strict) or only the object
// with its tool.
struct PushWaypoint {
  Eigen::Isometry3d tcp;
  const ExactChecker* check;
};

namespace {
struct PushCheckers {
  const ExactChecker &strict_before, &strict_after, &touch_before, &touch_after;
};

// The TCP's waypoints with a tool frame `at_contact` at contact c: `n_in` steps in over the
// standoff, `n_push` along the push (the contact carried by the object, the tool turning with
// it), `n_in` back out along the contact normal at the push's end.
std::vector<PushWaypoint> push_waypoints(const Eigen::Isometry3d& at_contact, const PushContact& c,
                                         const ObjectMotion& motion, double standoff, int n_in, int n_push,
                                         const PushCheckers& k) {
  std::vector<PushWaypoint> way;
  for (int i = 0; i <= n_in; ++i) {
    Eigen::Isometry3d f = at_contact;
    f.translation() -= standoff * (1 - double(i) / n_in) * c.direction;
    way.push_back({f, 2 * i < n_in ? &k.strict_before : &k.touch_before});
  }
  for (int i = 1; i <= n_push; ++i) {
    const double s = double(i) / n_push;
    way.push_back({motion.at(s) * at_contact, s <= 0.5 ? &k.touch_before : &k.touch_after});
  }
  const Eigen::Isometry3d at_end = way.back().tcp;
  const Eigen::Vector3d end_direction = motion.at(1).linear() * c.direction;
  for (int i = 1; i <= n_in; ++i) {
    Eigen::Isometry3d f = at_end;
    f.translation() -= standoff * double(i) / n_in * end_direction;
    way.push_back({f, 2 * i <= n_in ? &k.touch_after : &k.strict_after});
  }
  return way;
}
}  // namespace

JointPath PushPlanner::cartesian_path(const std::vector<PushWaypoint>& way, const Kinematics& kin,
                                      std::mt19937_64& rng) const {
  IkOptions first_ik;
  first_ik.max_restarts = 8;
  IkOptions step_ik;
  step_ik.max_restarts = 0;
  const IkSolver solve_first(kin, first_ik), solve_step(kin, step_ik);
  const Eigen::Isometry3d tcp_inv = spec_.tcp.inverse();
  const IkResult first = solve_first.solve(way[0].tcp * tcp_inv, start_, rng);
  if (!first.success || !way[0].check->is_free(first.q)) return {};
  JointPath cart{std::vector<double>(first.q.data(), first.q.data() + first.q.size())};
  Eigen::VectorXd prev = first.q;
  for (std::size_t w = 1; w < way.size(); ++w) {
    const IkResult r = solve_step.solve(way[w].tcp * tcp_inv, prev, rng);
    const ExactChecker* check = way[w].check;
    if (!r.success || (r.q - prev).cwiseAbs().maxCoeff() > kMaxJointStep ||
        !segment_valid(prev, r.q, resolution_, [check](const Eigen::VectorXd& q) { return check->is_free(q); }))
      return {};
    cart.emplace_back(r.q.data(), r.q.data() + r.q.size());
    prev = r.q;
  }
  return cart;
}

std::optional<PushPlan> PushPlanner::plan_action(const InHandAction& a) {
  const GraspGraph& graph = world_.grasp_graph();
  const Eigen::Isometry3d before = graph.tcp_pose(a.from_state), after = graph.tcp_pose(a.to_state);
  const double opening = std::max(graph.opening(a.from_state), graph.opening(a.to_state));
  const Kinematics& arm = world_.kinematics_at(opening);
  const ObjectMotion motion = object_motion(arm.tip_pose(q0_), before, after);
  const std::vector<PushContact> contacts = push_contacts(world_.object().mesh, motion, kContacts, contact_spacing_);
  if (contacts.empty()) return std::nullopt;

  // The pusher with the grasping fingers at this action's opening, and the object as an obstacle
  // before and after the action: nothing may touch it, or only the tool (the held object always
  // touches the grasping hand).
  Kinematics kin(*kin_);
  const RobotModel& m = kin.model();
  for (int l : world_.hand().links)
    for (std::size_t j = 0; j < m.joints.size(); ++j)
      if (m.joints[j].child == l && m.joints[j].type != JointType::Fixed && m.joints[j].mimic < 0)
        kin.set_joint_value(m.joints[j].name, arm.joint_value(int(j), q0_));
  std::vector<int> hand_and_tool = world_.hand().links;
  hand_and_tool.insert(hand_and_tool.end(), tool_.begin(), tool_.end());
  const ExactChecker pusher = exact_->with_kinematics(kin);
  const CollisionMesh& mesh = world_.object_mesh();
  const ExactChecker strict_before = pusher.with_attached(mesh, kin.base_link(), motion.before, world_.hand().links);
  const ExactChecker strict_after = pusher.with_attached(mesh, kin.base_link(), motion.after, world_.hand().links);
  const ExactChecker touch_before = pusher.with_attached(mesh, kin.base_link(), motion.before, hand_and_tool);
  const ExactChecker touch_after = pusher.with_attached(mesh, kin.base_link(), motion.after, hand_and_tool);
  const PushCheckers checkers{strict_before, strict_after, touch_before, touch_after};
  const ValidityFn free_before = [&](const Eigen::VectorXd& q) { return strict_before.is_free(q); };
  const ValidityFn free_after = [&](const Eigen::VectorXd& q) { return strict_after.is_free(q); };

  std::mt19937_64 rng(seed_ ^ (std::uint64_t(a.from_state) * 0x9E3779B97F4A7C15ull + std::uint64_t(a.to_state)));
  const int n_in = std::max(1, int(std::ceil(spec_.standoff / spec_.step)));
  for (const PushContact& c : contacts) {
    const double travel = motion.sweep((c.point - motion.pivot).norm());
    const int n_push = std::max({1, int(std::ceil(travel / spec_.step)), int(std::ceil(motion.angle / kMaxTurnStep))});
    for (const Eigen::Isometry3d& at_contact : tool_frames(c.point, c.direction)) {
      const JointPath cart =
          cartesian_path(push_waypoints(at_contact, c, motion, spec_.standoff, n_in, n_push, checkers), kin, rng);
      if (cart.empty()) continue;
      MotionBudget budget;
      budget.resolution = resolution_;
      budget.iterations = spec_.plan_iterations;
      budget.seconds = spec_.plan_time;
      budget.seed = rng();
      // Between the start and `to`, either way: planned from the start, on the shared tree.
      auto connect = [&](const Eigen::VectorXd& to, const ValidityFn& valid, bool back) -> JointPath {
        JointPath p;
        if (segment_valid(start_, to, resolution_, valid)) {
          p = {std::vector<double>(start_.data(), start_.data() + start_.size()),
               std::vector<double>(to.data(), to.data() + to.size())};
        } else {
          std::lock_guard<std::mutex> lock(tree_mutex_);
          p = plan_free_motion(kin, valid, start_, to, budget, &tree_);
        }
        if (back) std::reverse(p.begin(), p.end());
        return p;
      };
      const JointPath in = connect(vec(cart.front()), free_before, false);
      if (in.empty()) continue;
      const JointPath out = connect(vec(cart.back()), free_after, true);
      if (out.empty()) continue;
      PushPlan p;
      p.contact = c.point;
      p.direction = c.direction;
      p.object_before = motion.before;
      p.object_after = motion.after;
      p.grasp_after = after;
      p.path = in;
      p.path.insert(p.path.end(), cart.begin() + 1, cart.end());
      p.push_begin = int(in.size()) - 1 + n_in;
      p.push_end = p.push_begin + n_push;
      p.path.insert(p.path.end(), out.begin() + 1, out.end());
      return p;
    }
  }
  return std::nullopt;
}

}  // namespace dmgplace::runtime
