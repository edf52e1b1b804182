#include "dmgplace/runtime/collision/exact_checker.hpp"
#include "dmgplace/runtime/collision/fcl_geometry.hpp"
#include "dmgplace/runtime/geometry/convex_gap.hpp"

#include "dmgplace/runtime/motion/segment_check.hpp"

#include <fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance.h>
#include <fcl/fcl.h>
#include <octomap/octomap.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {
namespace {
using Geometry = std::shared_ptr<fcl::CollisionGeometryd>;

// Collision BVHs use OBB nodes (see the constructor's comment). Distance queries need RSS nodes:
// links build an OBBRSS copy when first asked (DistanceGeometry).
Geometry make_geometry(const Shape& s, bool for_distance = false) {
  return fcl_geometry(s, for_distance ? FclMeshNodes::Obbrss : FclMeshNodes::Obb);
}

// FCL's CollisionObject constructor recomputes its geometry's local AABB: a write to the geometry,
// which per-grasp checkers on every planner thread share (all BVHs are shared). Constructions are
// serialised, and only they read those bounds (PooledObject keeps its own copy): nothing else
// writes to a geometry after it is built.
std::mutex& fcl_object_mutex() {
  static std::mutex m;
  return m;
}

class Placed {
 public:
  Placed(const Geometry& g, const Eigen::Isometry3d& t) {
    std::lock_guard<std::mutex> lock(fcl_object_mutex());
    obj_.emplace(g, t.linear(), t.translation());
  }
  fcl::CollisionObjectd* get() { return &*obj_; }

 private:
  std::optional<fcl::CollisionObjectd> obj_;
};

// A link shape's geometry for distance queries, built on first use: only self-distance baking and
// tests ask, so planning start-up builds no second hierarchy. Primitives serve both kinds of query
// as they are.
class DistanceGeometry {
 public:
  DistanceGeometry(const Shape& shape, const Geometry& collision) : shape_(&shape) {
    if (shape.type != ShapeType::Mesh) geometry_ = collision;
  }
  const Geometry& get() {
    std::call_once(once_, [this] {
      if (!geometry_) geometry_ = make_geometry(*shape_, true);
    });
    return geometry_;
  }

 private:
  const Shape* shape_;  // in the robot model, which outlives every checker of it
  std::once_flag once_;
  Geometry geometry_;
};

struct Part {
  int link;                                    // robot link, or -1 for the attached object
  Geometry geometry;                           // for collision queries
  std::shared_ptr<DistanceGeometry> distance;  // links only
  Eigen::Isometry3d local;                     // in the link frame
  std::shared_ptr<const ConvexSolid> convex;   // for gaps: the primitive, or a mesh's hull (null: none)
};

// FCL's CollisionObject constructor rewrites its geometry's local bounds (a mesh's radius passes
// through 0 and its square on the way there), and CollisionObject::computeAABB() reads them. Every
// query shares the geometry, and per-query checkers build objects while other queries run, so a
// pooled object copies the bounds once, under fcl_object_mutex, and places its AABB from the copy:
// no query reads a geometry's bounds while another thread may be writing them.
class PooledObject : public fcl::CollisionObjectd {
 public:
  explicit PooledObject(const Geometry& g)
      : fcl::CollisionObjectd(g), local_(g->aabb_local), center_(g->aabb_center), radius_(g->aabb_radius) {}
  void place(const Eigen::Isometry3d& pose) {
    setTransform(pose.linear(), pose.translation());
    if (pose.linear().isIdentity()) {  // as computeAABB: the local box, moved
      aabb = fcl::translate(local_, pose.translation());
    } else {  // the bounding sphere's box
      const Eigen::Vector3d c = pose * center_;
      aabb.min_ = c.array() - radius_;
      aabb.max_ = c.array() + radius_;
    }
  }

 private:
  fcl::AABBd local_;
  Eigen::Vector3d center_;
  double radius_;
};

// Two placed parts whose boxes are apart cannot touch (each box bounds its part: the local box
// moved, or its bounding sphere's). For two primitives fcl::collide goes straight to GJK, so the
// box test first saves most self pairs of a state.
bool may_touch(const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b) {
  return a->getAABB().overlap(b->getAABB());
}

// One CollisionObject per part, built once and reused: the constructor walks every vertex of a
// mesh (FCL recomputes the local AABB), far more than the query itself near an obstacle. A query
// leases a set, so concurrent queries never share one.
class ObjectPool {
 public:
  using Set = std::vector<std::unique_ptr<PooledObject>>;
  class Lease {
   public:
    Lease(ObjectPool& pool, const std::vector<Part>& parts) : pool_(&pool), set_(pool.acquire(parts)) {}
    ~Lease() { pool_->release(std::move(set_)); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    fcl::CollisionObjectd* place(std::size_t part, const Eigen::Isometry3d& pose) {
      PooledObject* o = (*set_)[part].get();
      o->place(pose);
      return o;
    }

   private:
    ObjectPool* pool_;
    std::unique_ptr<Set> set_;
  };

 private:
  std::unique_ptr<Set> acquire(const std::vector<Part>& parts) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        auto s = std::move(free_.back());
        free_.pop_back();
        return s;
      }
    }
    auto s = std::make_unique<Set>();
    std::lock_guard<std::mutex> lock(fcl_object_mutex());
    for (const auto& p : parts) s->push_back(std::make_unique<PooledObject>(p.geometry));
    return s;
  }
  void release(std::unique_ptr<Set> s) {
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(s));
  }
  std::mutex mutex_;
  std::vector<std::unique_ptr<Set>> free_;
};
}  // namespace

struct CollisionMesh::Impl {
  Geometry geometry;
  std::vector<Part> parts;  // the mesh alone, for its object pool
  mutable ObjectPool pool;  // mesh_free places it without building an FCL object per call
};

CollisionMesh::CollisionMesh(const TriMesh& mesh) {
  if (mesh.empty()) throw Error("CollisionMesh", "mesh", "empty");
  auto impl = std::make_shared<Impl>();
  impl->geometry = fcl_mesh(mesh, FclMeshNodes::Obb);
  impl->parts.push_back({-1, impl->geometry, nullptr, Eigen::Isometry3d::Identity(), nullptr});
  this->impl = impl;
}

struct ExactChecker::Impl {
  std::vector<Part> parts;  // robot link geometry (+ attached object, link = its carrier link)
  std::vector<int> part_is_object;
  std::vector<std::string> link_names;
  std::vector<char> moving;
  std::vector<std::pair<int, int>> self_pairs;  // part index pairs
  // Environment: objects with names, in a broadphase manager.
  std::shared_ptr<std::vector<std::unique_ptr<fcl::CollisionObjectd>>> env_objects;
  std::shared_ptr<std::vector<std::string>> env_names;
  std::shared_ptr<fcl::DynamicAABBTreeCollisionManagerd> env;
  std::vector<int> touching;                                          // links the attached object may touch
  std::shared_ptr<ObjectPool> pool = std::make_shared<ObjectPool>();  // per parts list, never copied
  bool env_primitives = true;                                         // every scene shape is a box, cylinder or sphere
  bool link_meshes = false;  // some link shape is a mesh (FCL tests it through a hierarchy)
  // The scene's primitives as convex solids with their poses, for gaps (when env_primitives).
  std::shared_ptr<std::vector<std::pair<ConvexSolid, Eigen::Isometry3d>>> env_convex;
};

namespace {
struct EnvHit {
  bool hit = false;
  const fcl::CollisionObjectd* other = nullptr;
};

bool env_callback(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* data) {
  auto* hit = static_cast<EnvHit*>(data);
  fcl::CollisionRequestd req;
  fcl::CollisionResultd res;
  if (fcl::collide(a, b, req, res) > 0) {
    hit->hit = true;
    hit->other = a->getUserData() ? a : b;
    return true;  // stop
  }
  return false;
}

void build_self_pairs(ExactChecker::Impl& impl, const Kinematics& kin) {
  const auto& allowed = kin.model().allowed_pairs;
  auto is_allowed = [&](int a, int b) {
    if (a == b) return true;
    for (auto [x, y] : allowed)
      if ((x == a && y == b) || (x == b && y == a)) return true;
    return false;
  };
  impl.self_pairs.clear();
  for (std::size_t i = 0; i < impl.parts.size(); ++i)
    for (std::size_t j = i + 1; j < impl.parts.size(); ++j) {
      const int a = impl.parts[i].link, b = impl.parts[j].link;
      const bool ao = impl.part_is_object[i], bo = impl.part_is_object[j];
      if (ao || bo) {
        const int other = ao ? b : a;
        if (ao && bo) continue;
        if (other == (ao ? a : b)) continue;  // the carrier link holds it
        if (std::find(impl.touching.begin(), impl.touching.end(), other) != impl.touching.end()) continue;
        impl.self_pairs.emplace_back(int(i), int(j));
        continue;
      }
      if (!impl.moving[std::size_t(a)] && !impl.moving[std::size_t(b)]) continue;
      if (!is_allowed(a, b)) impl.self_pairs.emplace_back(int(i), int(j));
    }
}
}  // namespace

// The scene's objects (in a fresh broadphase manager) and, when all are primitives, their convex
// solids: everything of a checker that depends on the scene.
static void set_environment(ExactChecker::Impl& impl, const Scene& env, double scan_resolution) {
  impl.env_primitives = true;
  impl.env_objects = std::make_shared<std::vector<std::unique_ptr<fcl::CollisionObjectd>>>();
  impl.env_names = std::make_shared<std::vector<std::string>>();
  impl.env = std::make_shared<fcl::DynamicAABBTreeCollisionManagerd>();
  impl.env_convex = std::make_shared<std::vector<std::pair<ConvexSolid, Eigen::Isometry3d>>>();
  for (const auto& o : env.objects)
    for (const auto& s : o.shapes) {
      impl.env_primitives &= s.type != ShapeType::Mesh;
      if (s.type != ShapeType::Mesh) impl.env_convex->emplace_back(*ConvexSolid::of(s), s.origin);
      impl.env_names->push_back(o.name);
      auto obj = std::make_unique<fcl::CollisionObjectd>(make_geometry(s), s.origin.linear(), s.origin.translation());
      obj->setUserData(reinterpret_cast<void*>(impl.env_names->size()));  // 1-based name index
      obj->computeAABB();
      impl.env_objects->push_back(std::move(obj));
    }
  if (env.points.rows() > 0) {
    impl.env_primitives = false;
    auto tree = std::make_shared<octomap::OcTree>(scan_resolution);
    for (Eigen::Index i = 0; i < env.points.rows(); ++i)
      tree->updateNode(octomap::point3d(float(env.points(i, 0)), float(env.points(i, 1)), float(env.points(i, 2))),
                       true);
    tree->updateInnerOccupancy();
    impl.env_names->push_back("scan");
    auto obj = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::OcTreed>(tree));
    obj->setUserData(reinterpret_cast<void*>(impl.env_names->size()));
    obj->computeAABB();
    impl.env_objects->push_back(std::move(obj));
  }
  for (auto& o : *impl.env_objects) impl.env->registerObject(o.get());
  impl.env->setup();
}

ExactChecker::ExactChecker(const Kinematics& kin, const Scene& env, double scan_resolution) : kin_(&kin) {
  auto impl = std::make_shared<Impl>();
  const auto& m = kin.model();
  for (std::size_t l = 0; l < m.links.size(); ++l) {
    impl->link_names.push_back(m.links[l].name);
    for (const auto& s : m.links[l].collision) {
      Geometry g = make_geometry(s);
      std::shared_ptr<const ConvexSolid> convex;
      if (auto c = ConvexSolid::of(s)) convex = std::make_shared<const ConvexSolid>(std::move(*c));
      impl->parts.push_back({int(l), g, std::make_shared<DistanceGeometry>(s, g), s.origin, std::move(convex)});
      impl->link_meshes |= s.type == ShapeType::Mesh;
      impl->part_is_object.push_back(0);
    }
  }
  impl->moving = kin.moving_links();
  set_environment(*impl, env, scan_resolution);
  build_self_pairs(*impl, kin);
  impl_ = impl;
}

ExactChecker ExactChecker::with_scene(const Scene& environment, double scan_resolution) const {
  auto impl = std::make_shared<Impl>(*impl_);  // shares the robot's geometry (shared_ptrs)
  set_environment(*impl, environment, scan_resolution);
  ExactChecker c(*this);
  c.impl_ = impl;
  return c;
}

ExactChecker::~ExactChecker() = default;
ExactChecker::ExactChecker(const ExactChecker& o) = default;

ExactChecker ExactChecker::with_attached(const TriMesh& object, int link, const Eigen::Isometry3d& object_in_link,
                                         std::vector<int> touching_links) const {
  return with_attached(CollisionMesh(object), link, object_in_link, std::move(touching_links));
}

ExactChecker ExactChecker::with_attached(const CollisionMesh& object, int link, const Eigen::Isometry3d& object_in_link,
                                         std::vector<int> touching_links) const {
  if (link < 0 || std::size_t(link) >= kin_->model().links.size())
    throw Error("ExactChecker", "attached object", "link index out of range");
  auto impl = std::make_shared<Impl>(*impl_);  // shares the environment and geometry (shared_ptrs)
  impl->parts.push_back({link, object.impl->geometry, nullptr, object_in_link, nullptr});
  impl->part_is_object.push_back(1);
  impl->pool = std::make_shared<ObjectPool>();  // sets hold one object per part: a new list, a new pool
  impl->touching = std::move(touching_links);
  build_self_pairs(*impl, *kin_);
  ExactChecker c(*this);
  c.impl_ = impl;
  return c;
}

namespace {
bool hulls_apart(const ExactChecker::Impl& impl, std::size_t a, std::size_t b, const Eigen::Isometry3d& pose_a,
                 const Eigen::Isometry3d& pose_b);
}  // namespace

ExactCheck ExactChecker::check(const Eigen::VectorXd& q) const {
  thread_local std::vector<Eigen::Isometry3d> poses;
  kin_->link_poses(q, poses);
  const Impl& impl = *impl_;
  ExactCheck out;
  ObjectPool::Lease lease(*impl.pool, impl.parts);
  std::vector<fcl::CollisionObjectd*> objs(impl.parts.size());
  for (std::size_t i = 0; i < impl.parts.size(); ++i)
    objs[i] = lease.place(i, poses[std::size_t(impl.parts[i].link)] * impl.parts[i].local);
  for (std::size_t i = 0; i < impl.parts.size(); ++i) {
    if (!impl.moving[std::size_t(impl.parts[i].link)] && !impl.part_is_object[i]) continue;
    EnvHit hit;
    impl.env->collide(objs[i], &hit, env_callback);
    if (hit.hit) {
      out.environment_free = false;
      std::size_t name = reinterpret_cast<std::size_t>(hit.other->getUserData());
      out.contact =
          (impl.part_is_object[i] ? std::string("held object") : impl.link_names[std::size_t(impl.parts[i].link)]) +
          " / " + (name > 0 ? (*impl.env_names)[name - 1] : std::string("?"));
      return out;
    }
  }
  fcl::CollisionRequestd req;
  for (auto [a, b] : impl.self_pairs) {
    if (!may_touch(objs[std::size_t(a)], objs[std::size_t(b)])) continue;
    if (hulls_apart(impl, std::size_t(a), std::size_t(b), objs[std::size_t(a)]->getTransform(),
                    objs[std::size_t(b)]->getTransform()))
      continue;
    fcl::CollisionResultd res;
    if (fcl::collide(objs[std::size_t(a)], objs[std::size_t(b)], req, res) > 0) {
      out.self_free = false;
      auto name = [&](int k) {
        return impl.part_is_object[std::size_t(k)] ? std::string("held object")
                                                   : impl.link_names[std::size_t(impl.parts[std::size_t(k)].link)];
      };
      out.contact = name(a) + " / " + name(b);
      return out;
    }
  }
  return out;
}

namespace {
// convex_gap's bound is rigorous up to rounding; a gap counts only beyond 0.1 mm, so what it
// certifies stays clear of the exact layer's own contact tolerance too.
constexpr double kGapTolerance = 1e-4;

// The scene's primitives by the gap between their bounding balls and the part's, nearest first
// (this thread's list, valid until the next call).
const std::vector<std::pair<double, std::size_t>>& by_ball_gap(
    const ConvexSolid& part, const Eigen::Isometry3d& pose,
    const std::vector<std::pair<ConvexSolid, Eigen::Isometry3d>>& env) {
  thread_local std::vector<std::pair<double, std::size_t>> order;
  const Eigen::Vector3d c = pose * part.center();
  order.clear();
  for (std::size_t k = 0; k < env.size(); ++k)
    order.emplace_back((c - env[k].second * env[k].first.center()).norm() - part.radius() - env[k].first.radius(), k);
  std::sort(order.begin(), order.end());
  return order;
}

// A convex part at `pose` against the scene's primitives: its gap (GJK's rigorous lower bound, less
// the tolerance), asked only as far as `enough` needs. Nearest bounding balls first: a solid whose
// ball is farther than the gap so far cannot lower it.
// `hints`: one per scene primitive, where this part's last query of each ended (convex_gap).
double part_environment_gap(const ConvexSolid& part, const Eigen::Isometry3d& pose,
                            const std::vector<std::pair<ConvexSolid, Eigen::Isometry3d>>& env, double enough,
                            double gap, GapHint* hints) {
  const auto& order = by_ball_gap(part, pose, env);
  for (const auto& [ball_gap, k] : order) {
    // Past `enough` by the margin a computed gap gives up, a ball proves enough on its own.
    if (ball_gap >= gap || ball_gap - kGapTolerance > enough || gap <= 0) break;
    gap = std::min(gap, convex_gap(part, pose, env[k].first, env[k].second, 1e-5, enough + kGapTolerance, &hints[k]) -
                            kGapTolerance);
  }
  return gap;
}

// part_environment_gap for a time instead of a gap (ExactChecker::link_environment_time): each
// primitive's gap and separating direction go to `time`; the smallest time so far is `t`, and a
// primitive whose ball is farther than `reach` of it cannot end it sooner.
double part_environment_time(const ConvexSolid& part, const Eigen::Isometry3d& pose,
                             const std::vector<std::pair<ConvexSolid, Eigen::Isometry3d>>& env, double enough_gap,
                             double enough_time, const std::function<double(double, const Eigen::Vector3d&)>& time,
                             const std::function<double(double)>& reach, double t, GapHint* hints) {
  const auto& order = by_ball_gap(part, pose, env);
  double bound = reach(std::min(t, enough_time));
  for (const auto& [ball_gap, k] : order) {
    if (t <= 0 || ball_gap - kGapTolerance >= bound) break;  // this ball, and every farther one, lasts longer
    Eigen::Vector3d n;
    double gap = convex_gap(part, pose, env[k].first, env[k].second, 1e-5, enough_gap + kGapTolerance, &hints[k], &n) -
                 kGapTolerance;
    double tk = gap > 0 ? time(gap, n) : 0.0;
    if (gap > enough_gap && tk < enough_time) {  // stopped early, yet short: the whole gap
      gap = convex_gap(part, pose, env[k].first, env[k].second, 1e-5, std::numeric_limits<double>::infinity(),
                       &hints[k], &n) -
            kGapTolerance;
      tk = gap > 0 ? time(gap, n) : 0.0;
    }
    if (tk < t) {
      t = tk;
      bound = reach(std::min(t, enough_time));
    }
  }
  return t;
}

// This thread's gap hints for the checker geometry `owner` (n of them), kept from query to query:
// the queries along a motion ask the same parts and primitives a little apart. Another owner
// starts afresh (hints only speed GJK up; any hint gives the same rigorous bounds).
GapHint* thread_gap_hints(const void* owner, std::size_t n) {
  thread_local const void* last = nullptr;
  thread_local std::vector<GapHint> hints;
  if (last != owner || hints.size() != n) {
    last = owner;
    hints.assign(n, GapHint{});
  }
  return hints.data();
}

// Parts a and b whose convex hulls GJK proves apart: their meshes are apart too (a hull holds its
// mesh). Where two meshes are near (two arms side by side, a pusher at the held object) FCL's
// mesh-mesh descent visits many node pairs; the hulls settle most such pairs at a fraction of it.
// Two primitives are not asked: FCL's own test of them is already a convex one.
bool hulls_apart(const ExactChecker::Impl& impl, std::size_t a, std::size_t b, const Eigen::Isometry3d& pose_a,
                 const Eigen::Isometry3d& pose_b) {
  const Part &pa = impl.parts[a], &pb = impl.parts[b];
  if (!pa.convex || !pb.convex) return false;
  if (pa.geometry->getObjectType() != fcl::OT_BVH && pb.geometry->getObjectType() != fcl::OT_BVH) return false;
  const std::size_t np = impl.parts.size(), ne = impl.env_convex ? impl.env_convex->size() : 0;
  GapHint* hints = thread_gap_hints(&impl, np * ne + np * np) + np * ne;
  return convex_gap(*pa.convex, pose_a, *pb.convex, pose_b, 1e-5, kGapTolerance, &hints[a * np + b]) > kGapTolerance;
}
}  // namespace

bool ExactChecker::links_free(const std::vector<std::pair<int, Eigen::Isometry3d>>& link_poses) const {
  // FCL alone: proving convex links apart by their gaps first was slower here (the placement's
  // hand check: the hand sits near the support, where GJK iterates long: docs/perf-log.md).
  ObjectPool::Lease lease(*impl_->pool, impl_->parts);
  for (std::size_t i = 0; i < impl_->parts.size(); ++i) {
    const Part& p = impl_->parts[i];
    if (p.link < 0) continue;
    for (const auto& [link, pose] : link_poses) {
      if (link != p.link) continue;
      EnvHit hit;
      impl_->env->collide(lease.place(i, pose * p.local), &hit, env_callback);
      if (hit.hit) return false;
    }
  }
  return true;
}

bool ExactChecker::mesh_free(const CollisionMesh& mesh, const Eigen::Isometry3d& pose, std::string* contact) const {
  ObjectPool::Lease lease(mesh.impl->pool, mesh.impl->parts);
  EnvHit hit;
  impl_->env->collide(lease.place(0, pose), &hit, env_callback);
  if (hit.hit && contact) {
    const std::size_t name = reinterpret_cast<std::size_t>(hit.other->getUserData());
    *contact = name > 0 ? (*impl_->env_names)[name - 1] : std::string("?");
  }
  return !hit.hit;
}

bool ExactChecker::links_environment_free(const std::vector<Eigen::Isometry3d>& poses, const int* links, int count,
                                          bool object, const std::uint64_t* masks) const {
  if (count == 0 && !object) return true;
  if (poses.size() != kin_->model().links.size())
    throw Error("ExactChecker", "link poses", "one pose per link expected");
  const Impl& impl = *impl_;
  ObjectPool::Lease lease(*impl.pool, impl.parts);
  const auto& env = *impl.env_objects;
  for (std::size_t i = 0; i < impl.parts.size(); ++i) {
    const Part& p = impl.parts[i];
    std::uint64_t mask = 0;
    if (impl.part_is_object[i]) {
      if (!object) continue;
    } else {
      const int* at = std::find(links, links + count, p.link);
      if (at == links + count) continue;
      if (masks) mask = masks[at - links];
    }
    fcl::CollisionObjectd* obj = lease.place(i, poses[std::size_t(p.link)] * p.local);
    if (mask != 0 && env.size() >= std::size_t(64 - __builtin_clzll(mask))) {
      // Only the named shapes can touch it: test those, no broadphase.
      fcl::CollisionRequestd req;
      for (std::uint64_t m = mask; m; m &= m - 1) {
        fcl::CollisionResultd res;
        if (fcl::collide(obj, env[std::size_t(__builtin_ctzll(m))].get(), req, res) > 0) return false;
      }
      continue;
    }
    EnvHit hit;
    impl.env->collide(obj, &hit, env_callback);
    if (hit.hit) return false;
  }
  return true;
}

bool ExactChecker::link_pairs_free(const std::vector<Eigen::Isometry3d>& poses, const std::pair<int, int>* pairs,
                                   int count) const {
  if (count == 0) return true;
  if (poses.size() != kin_->model().links.size())
    throw Error("ExactChecker", "link poses", "one pose per link expected");
  const Impl& impl = *impl_;
  fcl::CollisionRequestd req;
  ObjectPool::Lease lease(*impl.pool, impl.parts);
  for (auto [a, b] : impl.self_pairs) {
    const int la = impl.parts[std::size_t(a)].link, lb = impl.parts[std::size_t(b)].link;
    if (impl.part_is_object[std::size_t(a)] || impl.part_is_object[std::size_t(b)]) continue;
    bool wanted = false;
    for (int i = 0; i < count; ++i)
      wanted |= (pairs[i].first == la && pairs[i].second == lb) || (pairs[i].first == lb && pairs[i].second == la);
    if (!wanted) continue;
    const auto& pa = impl.parts[std::size_t(a)];
    const auto& pb = impl.parts[std::size_t(b)];
    fcl::CollisionObjectd* oa = lease.place(std::size_t(a), poses[std::size_t(la)] * pa.local);
    fcl::CollisionObjectd* ob = lease.place(std::size_t(b), poses[std::size_t(lb)] * pb.local);
    fcl::CollisionResultd res;
    if (may_touch(oa, ob) &&
        !hulls_apart(impl, std::size_t(a), std::size_t(b), oa->getTransform(), ob->getTransform()) &&
        fcl::collide(oa, ob, req, res) > 0)
      return false;
  }
  return true;
}

std::vector<std::pair<int, int>> ExactChecker::colliding_link_pairs(const std::vector<Eigen::Isometry3d>& poses) const {
  if (poses.size() != kin_->model().links.size())
    throw Error("ExactChecker", "link poses", "one pose per link expected");
  const Impl& impl = *impl_;
  fcl::CollisionRequestd req;
  ObjectPool::Lease lease(*impl.pool, impl.parts);
  std::vector<std::pair<int, int>> out;
  const std::size_t nl = kin_->model().links.size();
  std::vector<char> allowed(nl * nl, 0);
  for (auto [x, y] : kin_->model().allowed_pairs)
    if (x >= 0 && y >= 0 && std::size_t(x) < nl && std::size_t(y) < nl)
      allowed[std::size_t(x) * nl + std::size_t(y)] = allowed[std::size_t(y) * nl + std::size_t(x)] = 1;
  // Every pair, the ones no chain joint moves too (self_pairs leaves those out): the question is
  // which pairs may ever touch, under any joint, not only under this chain's.
  for (std::size_t a = 0; a < impl.parts.size(); ++a)
    for (std::size_t b = a + 1; b < impl.parts.size(); ++b) {
      if (impl.part_is_object[a] || impl.part_is_object[b]) continue;
      const auto& pa = impl.parts[a];
      const auto& pb = impl.parts[b];
      if (pa.link == pb.link) continue;
      const std::pair<int, int> links{std::min(pa.link, pb.link), std::max(pa.link, pb.link)};
      if (allowed[std::size_t(pa.link) * nl + std::size_t(pb.link)]) continue;
      if (std::find(out.begin(), out.end(), links) != out.end()) continue;  // another shape of the pair hit already
      fcl::CollisionObjectd* oa = lease.place(a, poses[std::size_t(pa.link)] * pa.local);
      fcl::CollisionObjectd* ob = lease.place(b, poses[std::size_t(pb.link)] * pb.local);
      fcl::CollisionResultd res;
      if (may_touch(oa, ob) && !hulls_apart(impl, a, b, oa->getTransform(), ob->getTransform()) &&
          fcl::collide(oa, ob, req, res) > 0)
        out.push_back(links);
    }
  return out;
}

namespace {
const fcl::BVHModel<fcl::OBBRSSd>* as_mesh(const Geometry& g) {
  return dynamic_cast<const fcl::BVHModel<fcl::OBBRSSd>*>(g.get());
}

// The two links' convex hulls' gap (GJK's proven bound, less its tolerance; 0 when a part has no
// hull), each part pair's GJK started afresh: the same value whichever thread asks, as the baked
// tables must be (link_pair_gap's warm starts can move the bound within GJK's tolerance).
double hull_gap(const ExactChecker::Impl& impl, const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b) {
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < impl.parts.size() && gap > 0; ++i) {
    const Part& pa = impl.parts[i];
    if (impl.part_is_object[i] || pa.link != link_a) continue;
    if (!pa.convex) return 0.0;
    for (std::size_t j = 0; j < impl.parts.size() && gap > 0; ++j) {
      const Part& pb = impl.parts[j];
      if (impl.part_is_object[j] || pb.link != link_b) continue;
      if (!pb.convex) return 0.0;
      GapHint fresh{};
      gap = std::min(gap, convex_gap(*pa.convex, poses[std::size_t(link_a)] * pa.local, *pb.convex,
                                     poses[std::size_t(link_b)] * pb.local, 1e-5,
                                     std::numeric_limits<double>::infinity(), &fresh) -
                              kGapTolerance);
    }
  }
  return std::max(gap, 0.0);
}

// Triangle `tri` of mesh `m` placed at `pose`.
void world_triangle(const fcl::BVHModel<fcl::OBBRSSd>& m, int tri, const Eigen::Isometry3d& pose,
                    fcl::Vector3d out[3]) {
  const fcl::Triangle& t = m.tri_indices[tri];
  for (int k = 0; k < 3; ++k) out[k] = pose * m.vertices[t[std::size_t(k)]];
}
}  // namespace

double ExactChecker::link_distance(const Eigen::VectorXd& q, int link_a, int link_b, LinkWitness* witness) const {
  return link_distance_below(q, link_a, link_b, std::numeric_limits<double>::infinity(), witness);
}

double ExactChecker::link_distance_below(const Eigen::VectorXd& q, int link_a, int link_b, double attained,
                                         LinkWitness* witness) const {
  thread_local std::vector<Eigen::Isometry3d> poses;
  kin_->link_poses(q, poses);
  double best = attained;
  if (witness) *witness = LinkWitness{};
  for (std::size_t i = 0; i < impl_->parts.size(); ++i) {
    const Part& pa = impl_->parts[i];
    if (pa.link != link_a) continue;
    for (std::size_t j = 0; j < impl_->parts.size(); ++j) {
      const Part& pb = impl_->parts[j];
      if (pb.link != link_b) continue;
      Placed oa(pa.distance->get(), poses[std::size_t(link_a)] * pa.local),
          ob(pb.distance->get(), poses[std::size_t(link_b)] * pb.local);
      fcl::CollisionRequestd creq;
      fcl::CollisionResultd cres;
      // FCL's distance between primitives is unsigned inside, so they are tested for contact first.
      // Two meshes need not be: a triangle pair that crosses is 0 apart, which ends the search.
      const bool meshes = as_mesh(pa.distance->get()) && as_mesh(pb.distance->get());
      if (!meshes && fcl::collide(oa.get(), ob.get(), creq, cres) > 0) return 0.0;
      fcl::DistanceRequestd req;
      fcl::DistanceResultd res;
      // FCL prunes every node pair no closer than what it holds: starting it from the closest
      // distance known (attained, so the minimum is unchanged) skips most of the traversal.
      if (meshes) res.min_distance = best;
      fcl::distance(oa.get(), ob.get(), req, res);
      if (std::max(0.0, res.min_distance) < best) {
        best = std::max(0.0, res.min_distance);
        // For meshes FCL names the two closest triangles (b1, b2).
        if (witness && as_mesh(pa.distance->get()) && as_mesh(pb.distance->get()))
          *witness = {int(i), int(res.b1), int(j), int(res.b2)};
      }
    }
  }
  return best;
}

double ExactChecker::link_distance_within(const Eigen::VectorXd& q, int link_a, int link_b, double tolerance,
                                          const std::vector<LinkWitness>& near, LinkWitness* witness) const {
  const Impl& impl = *impl_;
  thread_local std::vector<Eigen::Isometry3d> poses;
  kin_->link_poses(q, poses);
  // Any two triangles of the meshes are at least the links' distance apart: the closest of the
  // witnesses' pairs bounds it from above.
  double upper = std::numeric_limits<double>::infinity();
  LinkWitness closest;
  for (const LinkWitness& w : near) {
    if (w.part_a < 0 || w.part_b < 0 || std::size_t(w.part_a) >= impl.parts.size() ||
        std::size_t(w.part_b) >= impl.parts.size())
      continue;
    const Part &pa = impl.parts[std::size_t(w.part_a)], &pb = impl.parts[std::size_t(w.part_b)];
    const auto *ma = as_mesh(pa.distance->get()), *mb = as_mesh(pb.distance->get());
    if (pa.link != link_a || pb.link != link_b || !ma || !mb || w.tri_a < 0 || w.tri_a >= ma->num_tris || w.tri_b < 0 ||
        w.tri_b >= mb->num_tris)
      continue;
    fcl::Vector3d A[3], B[3], on_a, on_b;
    world_triangle(*ma, w.tri_a, poses[std::size_t(link_a)] * pa.local, A);
    world_triangle(*mb, w.tri_b, poses[std::size_t(link_b)] * pb.local, B);
    const double d = fcl::detail::TriangleDistance<double>::triDistance(A, B, on_a, on_b);
    if (d < upper) upper = d, closest = w;
  }
  if (witness) *witness = closest;  // it attains `upper`: the pair to start from next door
  if (tolerance > 0 && std::isfinite(upper)) {
    const double lower = hull_gap(impl, poses, link_a, link_b);
    if (lower > 0 && upper - lower <= tolerance) return lower;
  }
  LinkWitness found;
  const double d = link_distance_below(q, link_a, link_b, upper, &found);
  if (witness && found.part_a >= 0) *witness = found;
  return d;
}

namespace {
// `link`'s convex parts against the scene in turn: each(part, pose, value, hints) lowers `value`
// (a gap or a time, from infinity) while it stays positive. 0 when the scene is not all primitives
// or a part has no hull.
template <class Each>
double over_link_parts(const ExactChecker::Impl& impl, const std::vector<Eigen::Isometry3d>& poses, int link,
                       Each&& each) {
  if (!impl.env_primitives) return 0.0;
  double value = std::numeric_limits<double>::infinity();
  const std::size_t np = impl.parts.size(), ne = impl.env_convex ? impl.env_convex->size() : 0;
  GapHint* hints = thread_gap_hints(&impl, np * ne + np * np);
  for (std::size_t i = 0; i < np && value > 0; ++i) {
    const Part& p = impl.parts[i];
    if (impl.part_is_object[i] || p.link != link) continue;
    if (!p.convex) return 0.0;
    value = each(*p.convex, poses[std::size_t(p.link)] * p.local, value, hints + i * ne);
  }
  return value;
}
}  // namespace

double ExactChecker::link_environment_gap(const std::vector<Eigen::Isometry3d>& poses, int link, double enough) const {
  return over_link_parts(*impl_, poses, link,
                         [&](const ConvexSolid& part, const Eigen::Isometry3d& pose, double gap, GapHint* hints) {
                           return part_environment_gap(part, pose, *impl_->env_convex, enough, gap, hints);
                         });
}

double ExactChecker::link_environment_time(const std::vector<Eigen::Isometry3d>& poses, int link, double enough_gap,
                                           double enough_time,
                                           const std::function<double(double, const Eigen::Vector3d&)>& time,
                                           const std::function<double(double)>& reach) const {
  const double t = over_link_parts(
      *impl_, poses, link, [&](const ConvexSolid& part, const Eigen::Isometry3d& pose, double sofar, GapHint* hints) {
        return part_environment_time(part, pose, *impl_->env_convex, enough_gap, enough_time, time, reach, sofar,
                                     hints);
      });
  // Shapes were skipped as lasting `enough_time`, not as lasting t.
  return std::min(t, enough_time);
}

bool ExactChecker::gaps_are_cheap() const {
  if (!impl_->env_primitives) return false;
  for (std::size_t i = 0; i < impl_->parts.size(); ++i)
    if (!impl_->part_is_object[i] && !impl_->parts[i].convex) return false;
  return true;
}

bool ExactChecker::links_have_meshes() const { return impl_->link_meshes; }

double ExactChecker::link_pair_gap(const std::vector<Eigen::Isometry3d>& poses, int link_a, int link_b,
                                   double enough) const {
  const Impl& impl = *impl_;
  double gap = std::numeric_limits<double>::infinity();
  const std::size_t np = impl.parts.size(), ne = impl.env_convex ? impl.env_convex->size() : 0;
  GapHint* hints = thread_gap_hints(&impl, np * ne + np * np) + np * ne;
  for (std::size_t i = 0; i < np && gap > 0; ++i) {
    const Part& pa = impl.parts[i];
    if (impl.part_is_object[i] || pa.link != link_a) continue;
    if (!pa.convex) return 0.0;
    for (std::size_t j = 0; j < np && gap > 0; ++j) {
      const Part& pb = impl.parts[j];
      if (impl.part_is_object[j] || pb.link != link_b) continue;
      if (!pb.convex) return 0.0;
      gap = std::min(
          gap, convex_gap(*pa.convex, poses[std::size_t(link_a)] * pa.local, *pb.convex,
                          poses[std::size_t(link_b)] * pb.local, 1e-5, enough + kGapTolerance, &hints[i * np + j]) -
                   kGapTolerance);
    }
  }
  return gap;
}

bool ExactChecker::segment_free(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution) const {
  return is_free(a) && segment_valid(a, b, resolution, [this](const Eigen::VectorXd& q) { return is_free(q); });
}

ExactChecker ExactChecker::with_kinematics(const Kinematics& kin) const {
  if (&kin.model() != &kin_->model())
    throw Error("ExactChecker", "kinematics",
                "a different robot model: only joint values outside the chain may differ");
  ExactChecker c(*this);
  c.kin_ = &kin;
  return c;
}

}  // namespace dmgplace::runtime
