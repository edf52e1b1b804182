#include "embree_mesh.hpp"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools::detail {
namespace {

RTCScene scene_of(void* s) { return static_cast<RTCScene>(s); }

struct QueryState {
  const TriMesh* mesh;
  const OrientedBox* box;
  bool hit = false;
};

Eigen::Vector3d vertex(const TriMesh& m, int t, int k) { return m.vertices.row(m.triangles(t, k)).transpose(); }

// Called by Embree for every triangle whose BVH bounds meet the query sphere around the box.
bool box_query_callback(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<QueryState*>(args->userPtr);
  if (st->hit) return false;
  const int t = int(args->primID);
  const auto& b = *st->box;
  const Eigen::Matrix3d rt = b.axes.transpose();
  const Eigen::Vector3d a = rt * (vertex(*st->mesh, t, 0) - b.center);
  const Eigen::Vector3d c1 = rt * (vertex(*st->mesh, t, 1) - b.center);
  const Eigen::Vector3d c2 = rt * (vertex(*st->mesh, t, 2) - b.center);
  if (triangle_overlaps_box(a, c1, c2, b.half)) {
    st->hit = true;
    args->query->radius = 0;  // shrinks the query: ends the traversal early
    return true;
  }
  return false;
}

// Projections of the triangle and the box onto `axis` are disjoint.
bool separated(const Eigen::Vector3d& axis, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
               const Eigen::Vector3d& c, const Eigen::Vector3d& h) {
  if (axis.squaredNorm() < 1e-30) return false;
  const double pa = axis.dot(a), pb = axis.dot(b), pc = axis.dot(c);
  const double r = h.x() * std::abs(axis.x()) + h.y() * std::abs(axis.y()) + h.z() * std::abs(axis.z());
  return std::min({pa, pb, pc}) > r || std::max({pa, pb, pc}) < -r;
}

}  // namespace

bool triangle_overlaps_box(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& h) {
  // Separating axis theorem: 3 box axes, the triangle normal, 9 edge cross products.
  for (int i = 0; i < 3; ++i)
    if (separated(Eigen::Vector3d::Unit(i), a, b, c, h)) return false;
  const Eigen::Vector3d e[3] = {b - a, c - b, a - c};
  if (separated(e[0].cross(e[1]), a, b, c, h)) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (separated(Eigen::Vector3d::Unit(i).cross(e[j]), a, b, c, h)) return false;
  return true;
}

EmbreeMesh::EmbreeMesh(const TriMesh& mesh) : mesh_(mesh) {
  RTCDevice device = rtcNewDevice("threads=1");
  if (!device) throw Error("embree", "", "cannot create an Embree device");
  device_ = device;
  RTCScene scene = rtcNewScene(device);
  scene_ = scene;
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), std::size_t(mesh.vertices.rows())));
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = float(mesh.vertices(i, k));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), std::size_t(mesh.triangles.rows())));
  for (Eigen::Index i = 0; i < mesh.triangles.rows(); ++i)
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = unsigned(mesh.triangles(i, k));
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  rtcCommitScene(scene);
}

EmbreeMesh::~EmbreeMesh() {
  if (scene_) rtcReleaseScene(scene_of(scene_));
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

std::optional<RayHit> EmbreeMesh::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                       double max_distance) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh{};
  rh.ray.org_x = float(origin.x());
  rh.ray.org_y = float(origin.y());
  rh.ray.org_z = float(origin.z());
  rh.ray.dir_x = float(dir.x());
  rh.ray.dir_y = float(dir.y());
  rh.ray.dir_z = float(dir.z());
  rh.ray.tnear = 0;
  rh.ray.tfar = float(max_distance);
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_of(scene_), &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  // Refine the distance in double against the hit triangle's plane (Embree works in float).
  const int t = int(rh.hit.primID);
  const Eigen::Vector3d a = vertex(mesh_, t, 0);
  const Eigen::Vector3d n = (vertex(mesh_, t, 1) - a).cross(vertex(mesh_, t, 2) - a);
  double d = rh.ray.tfar;
  const double den = n.dot(dir);
  if (std::abs(den) > 1e-12 * n.norm()) d = n.dot(a - origin) / den;
  return RayHit{d, t};
}

bool EmbreeMesh::overlaps(const OrientedBox& box) const {
  QueryState st{&mesh_, &box};
  RTCPointQuery q;
  q.x = float(box.center.x());
  q.y = float(box.center.y());
  q.z = float(box.center.z());
  q.time = 0;
  q.radius = float(box.half.norm() * (1 + 1e-5) + 1e-7);  // float rounding must not lose a candidate
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(scene_of(scene_), &q, &ctx, box_query_callback, &st);
  return st.hit;
}

}  // namespace dmgplace::tools::detail
