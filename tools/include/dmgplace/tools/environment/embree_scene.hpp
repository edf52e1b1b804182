#pragma once
// Embree 3 BVHs over an EnvironmentGeometry: closest-distance queries (rtcPointQuery with exact
// point-triangle / point-point callbacks) and all crossings of a vertical line (for inside tests
// and support surfaces). Embree stays inside the .cpp; queries are thread-safe.
#include <memory>
#include <vector>

#include "dmgplace/tools/environment/environment_geometry.hpp"

namespace dmgplace::tools {

struct ColumnHit {
  double z = 0;   // height where the vertical line crosses the triangle
  int mesh = -1;  // index into EnvironmentGeometry::meshes
  double nz = 0;  // z of the triangle's unit normal (> 0: facing up, the line leaves an outward mesh)
};

class EmbreeScene {
 public:
  // Keeps a pointer to `geometry`, which must outlive the scene.
  explicit EmbreeScene(const EnvironmentGeometry& geometry);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  const EnvironmentGeometry& geometry() const;
  // Distance from p to the nearest triangle or scan point, searching up to `radius`; +inf if
  // nothing lies within it.
  double distance(const Eigen::Vector3d& p, double radius) const;
  // The same, counting only obstacle parts strictly above height z_min (triangles clipped there).
  double distance_above(const Eigen::Vector3d& p, double radius, double z_min) const;
  // Every triangle crossing of the vertical line through (x, y) between z0 and z1, sorted by z,
  // an edge shared by two faces of one mesh counted once.
  std::vector<ColumnHit> column(double x, double y, double z0, double z1) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Tracks which closed meshes a vertical line is inside of while walking its hits upwards
// (winding number per mesh, so overlapping parts of one mesh stay inside).
class InsideTracker {
 public:
  explicit InsideTracker(const EnvironmentGeometry& g) : closed_(g.closed), winding_(g.meshes.size(), 0) {}
  void cross(const ColumnHit& h);
  bool inside() const { return inside_count_ > 0; }
  void reset();

 private:
  const std::vector<bool>& closed_;
  std::vector<int> winding_;
  std::vector<int> touched_;
  int inside_count_ = 0;
};

}  // namespace dmgplace::tools
