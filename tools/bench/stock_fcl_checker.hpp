#pragma once
// The benchmark baseline's validity checker: what MoveIt's FCL collision environment does for a
// state. One FCL object per link shape (mesh BVHs with OBBRSS nodes, as MoveIt's
// createCollisionGeometry builds them), the scene in a dynamic AABB tree, every moving link against
// it, then every self pair the SRDF does not allow. No distance field, no spheres, no certificates.
// Not part of the product: bench-mbm compares our planner with it.
#include <memory>

#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/runtime/collision/fcl_geometry.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::bench {

class StockFclChecker {
 public:
  // Scene shapes in the kinematics' base frame; scan points are refused (MotionBenchMaker scenes
  // have none). `kin` must outlive the checker.
  // `mesh_nodes`: OBBRSS as MoveIt builds meshes, or OBB as our exact layer does.
  StockFclChecker(const runtime::Kinematics& kin, const Scene& scene,
                  runtime::FclMeshNodes mesh_nodes = runtime::FclMeshNodes::Obbrss);
  ~StockFclChecker();
  StockFclChecker(const StockFclChecker&) = delete;
  StockFclChecker& operator=(const StockFclChecker&) = delete;

  // One planner thread at a time, as OMPL's RRTConnect calls it.
  bool is_free(const Eigen::VectorXd& q) const;

 private:
  struct Impl;
  const runtime::Kinematics* kin_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmgplace::bench
