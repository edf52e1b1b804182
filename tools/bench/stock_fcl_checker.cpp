#include "stock_fcl_checker.hpp"

#include <fcl/fcl.h>

#include <algorithm>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::bench {
namespace {
struct Part {
  int link;
  Eigen::Isometry3d local;
  std::unique_ptr<fcl::CollisionObjectd> object;
};

bool stop_at_first_contact(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* hit) {
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  if (fcl::collide(a, b, request, result) == 0) return false;
  *static_cast<bool*>(hit) = true;
  return true;
}
}  // namespace

struct StockFclChecker::Impl {
  mutable std::vector<Part> parts;
  std::vector<char> moving;                     // per link: moves with the chain
  std::vector<std::pair<int, int>> self_pairs;  // part indices
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> scene_objects;
  mutable fcl::DynamicAABBTreeCollisionManagerd scene;
  mutable std::vector<Eigen::Isometry3d> poses;
};

StockFclChecker::StockFclChecker(const runtime::Kinematics& kin, const Scene& scene, runtime::FclMeshNodes mesh_nodes)
    : kin_(&kin), impl_(std::make_unique<Impl>()) {
  if (scene.points.rows() > 0) throw Error("stock baseline", "scene", "scan points are not supported; give shapes");
  const RobotModel& m = kin.model();
  for (std::size_t l = 0; l < m.links.size(); ++l)
    for (const Shape& s : m.links[l].collision)
      impl_->parts.push_back(
          {int(l), s.origin, std::make_unique<fcl::CollisionObjectd>(runtime::fcl_geometry(s, mesh_nodes))});
  impl_->moving = kin.moving_links();
  auto allowed = [&](int a, int b) {
    return a == b || std::any_of(m.allowed_pairs.begin(), m.allowed_pairs.end(), [&](const auto& p) {
             return (p.first == a && p.second == b) || (p.first == b && p.second == a);
           });
  };
  for (std::size_t i = 0; i < impl_->parts.size(); ++i)
    for (std::size_t j = i + 1; j < impl_->parts.size(); ++j) {
      const int a = impl_->parts[i].link, b = impl_->parts[j].link;
      if ((impl_->moving[std::size_t(a)] || impl_->moving[std::size_t(b)]) && !allowed(a, b))
        impl_->self_pairs.emplace_back(int(i), int(j));
    }
  for (const auto& o : scene.objects)
    for (const Shape& s : o.shapes) {
      auto obj = std::make_unique<fcl::CollisionObjectd>(runtime::fcl_geometry(s, mesh_nodes), s.origin.linear(),
                                                         s.origin.translation());
      obj->computeAABB();
      impl_->scene.registerObject(obj.get());
      impl_->scene_objects.push_back(std::move(obj));
    }
  impl_->scene.setup();
}

StockFclChecker::~StockFclChecker() = default;

bool StockFclChecker::is_free(const Eigen::VectorXd& q) const {
  Impl& impl = *impl_;
  kin_->link_poses(q, impl.poses);
  for (Part& p : impl.parts) {
    const Eigen::Isometry3d pose = impl.poses[std::size_t(p.link)] * p.local;
    p.object->setTransform(pose.linear(), pose.translation());
    p.object->computeAABB();
  }
  for (Part& p : impl.parts) {
    if (!impl.moving[std::size_t(p.link)]) continue;
    bool hit = false;
    impl.scene.collide(p.object.get(), &hit, stop_at_first_contact);
    if (hit) return false;
  }
  fcl::CollisionRequestd request;
  for (auto [a, b] : impl.self_pairs) {
    fcl::CollisionResultd result;
    if (fcl::collide(impl.parts[std::size_t(a)].object.get(), impl.parts[std::size_t(b)].object.get(), request,
                     result) > 0)
      return false;
  }
  return true;
}

}  // namespace dmgplace::bench
