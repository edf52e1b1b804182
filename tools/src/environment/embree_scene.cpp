#include "dmgplace/tools/environment/embree_scene.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/environment/closest_point.hpp"

namespace dmgplace::tools {

struct EmbreeScene::Impl {
  const EnvironmentGeometry* g = nullptr;
  RTCDevice device = nullptr;
  RTCScene triangles = nullptr;  // geometry ID = mesh index
  RTCScene points = nullptr;     // one user geometry, primitive ID = point row
  ~Impl() {
    if (triangles) rtcReleaseScene(triangles);
    if (points) rtcReleaseScene(points);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

void check_device(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw Error("embree", what, "error code " + std::to_string(int(e)));
}

Eigen::Vector3d vertex(const TriMesh& m, int v) { return m.vertices.row(v).transpose(); }

void point_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* pts = static_cast<const RowMatrixX3d*>(args->geometryUserPtr);
  const auto r = pts->row(Eigen::Index(args->primID));
  RTCBounds* b = args->bounds_o;
  b->lower_x = std::nextafter(float(r(0)), -INFINITY);
  b->lower_y = std::nextafter(float(r(1)), -INFINITY);
  b->lower_z = std::nextafter(float(r(2)), -INFINITY);
  b->upper_x = std::nextafter(float(r(0)), INFINITY);
  b->upper_y = std::nextafter(float(r(1)), INFINITY);
  b->upper_z = std::nextafter(float(r(2)), INFINITY);
}

// Points never take part in ray casts; these only satisfy the user-geometry interface.
void no_intersect(const RTCIntersectFunctionNArguments*) {}
void no_occluded(const RTCOccludedFunctionNArguments*) {}

struct QueryState {
  const EnvironmentGeometry* g;
  Eigen::Vector3d p;
  double best2;
  bool above;  // count only geometry strictly above z_min
  double z_min;
};

// Accepts a closer primitive and shrinks the query so Embree culls everything farther.
bool accept(RTCPointQueryFunctionArguments* args, QueryState* s, double d2) {
  if (!(d2 < s->best2)) return false;
  s->best2 = d2;
  const float r = std::nextafter(float(std::sqrt(d2)), INFINITY);
  if (r < args->query->radius) args->query->radius = r;
  return true;
}

bool triangle_query(RTCPointQueryFunctionArguments* args) {
  auto* s = static_cast<QueryState*>(args->userPtr);
  const TriMesh& m = s->g->meshes[args->geomID];
  const auto t = m.triangles.row(Eigen::Index(args->primID));
  const Eigen::Vector3d a = vertex(m, t(0)), b = vertex(m, t(1)), c = vertex(m, t(2));
  const double d2 = s->above ? squared_distance_to_triangle_above(s->p, a, b, c, s->z_min)
                             : squared_distance_to_triangle(s->p, a, b, c);
  return accept(args, s, d2);
}

bool point_query(RTCPointQueryFunctionArguments* args) {
  auto* s = static_cast<QueryState*>(args->userPtr);
  const Eigen::Vector3d q = s->g->points.row(Eigen::Index(args->primID)).transpose();
  if (s->above && !(q.z() > s->z_min)) return false;
  return accept(args, s, (q - s->p).squaredNorm());
}

struct Collector {
  RTCIntersectContext ctx;  // first member: Embree hands the filter a pointer to it
  std::vector<std::pair<unsigned, unsigned>>* hits;
};

// Records every crossing and rejects it, so traversal goes on to the next one.
void collect(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<Collector*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    c->hits->emplace_back(RTCHitN_geomID(args->hit, args->N, i), RTCHitN_primID(args->hit, args->N, i));
    args->valid[i] = 0;
  }
}

double run_query(RTCScene scene, QueryState& s, double radius, RTCPointQueryFunction fn) {
  RTCPointQuery q;
  q.x = float(s.p.x());
  q.y = float(s.p.y());
  q.z = float(s.p.z());
  q.time = 0;
  q.radius = std::nextafter(float(radius), INFINITY);
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(scene, &q, &ctx, fn, &s);
  return s.best2;
}

}  // namespace

EmbreeScene::EmbreeScene(const EnvironmentGeometry& g) : impl_(std::make_unique<Impl>()) {
  impl_->g = &g;
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw Error("embree", "rtcNewDevice", "cannot create a device");
  impl_->triangles = rtcNewScene(impl_->device);
  // Robust (watertight) traversal so no crossing slips between two faces of a shared edge.
  rtcSetSceneFlags(impl_->triangles, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
  for (std::size_t id = 0; id < g.meshes.size(); ++id) {
    const TriMesh& m = g.meshes[id];
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), std::size_t(m.vertices.rows())));
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), std::size_t(m.triangles.rows())));
    check_device(impl_->device, "triangle buffers");
    for (Eigen::Index i = 0; i < m.vertices.size(); ++i) v[i] = float(m.vertices(i / 3, i % 3));
    for (Eigen::Index i = 0; i < m.triangles.size(); ++i) t[i] = unsigned(m.triangles(i / 3, i % 3));
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(impl_->triangles, geom, unsigned(id));
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(impl_->triangles);
  check_device(impl_->device, "triangle scene");
  if (g.points.rows() > 0) {
    impl_->points = rtcNewScene(impl_->device);
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, unsigned(g.points.rows()));
    rtcSetGeometryUserData(geom, const_cast<RowMatrixX3d*>(&g.points));
    rtcSetGeometryBoundsFunction(geom, point_bounds, const_cast<RowMatrixX3d*>(&g.points));
    rtcSetGeometryIntersectFunction(geom, no_intersect);
    rtcSetGeometryOccludedFunction(geom, no_occluded);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->points, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->points);
    check_device(impl_->device, "point scene");
  }
}

EmbreeScene::~EmbreeScene() = default;

const EnvironmentGeometry& EmbreeScene::geometry() const { return *impl_->g; }

double EmbreeScene::distance(const Eigen::Vector3d& p, double radius) const {
  QueryState s{impl_->g, p, radius * radius, false, 0};
  run_query(impl_->triangles, s, radius, triangle_query);
  if (impl_->points) run_query(impl_->points, s, std::sqrt(s.best2), point_query);
  return s.best2 < radius * radius ? std::sqrt(s.best2) : std::numeric_limits<double>::infinity();
}

double EmbreeScene::distance_above(const Eigen::Vector3d& p, double radius, double z_min) const {
  QueryState s{impl_->g, p, radius * radius, true, z_min};
  run_query(impl_->triangles, s, radius, triangle_query);
  if (impl_->points) run_query(impl_->points, s, std::sqrt(s.best2), point_query);
  return s.best2 < radius * radius ? std::sqrt(s.best2) : std::numeric_limits<double>::infinity();
}

std::vector<ColumnHit> EmbreeScene::column(double x, double y, double z0, double z1) const {
  std::vector<std::pair<unsigned, unsigned>> raw;
  Collector c;
  rtcInitIntersectContext(&c.ctx);
  c.ctx.filter = collect;
  c.hits = &raw;
  RTCRayHit rh{};
  rh.ray.org_x = float(x);
  rh.ray.org_y = float(y);
  rh.ray.org_z = float(z0);
  rh.ray.dir_z = 1;
  rh.ray.tnear = 0;
  rh.ray.tfar = float(z1 - z0);
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->triangles, &c.ctx, &rh);
  std::sort(raw.begin(), raw.end());
  raw.erase(std::unique(raw.begin(), raw.end()), raw.end());
  std::vector<ColumnHit> hits;
  hits.reserve(raw.size());
  for (auto [geom, prim] : raw) {
    const TriMesh& m = impl_->g->meshes[geom];
    const auto t = m.triangles.row(Eigen::Index(prim));
    const Eigen::Vector3d a = vertex(m, t(0)), b = vertex(m, t(1)), cc = vertex(m, t(2));
    const Eigen::Vector3d n = (b - a).cross(cc - a);
    const double len = n.norm();
    if (!(std::abs(n.z()) > 1e-12 * len)) continue;  // parallel to the line: no crossing
    // Exact plane height in double (Embree's hit distance is float).
    const double z = a.z() - (n.x() * (x - a.x()) + n.y() * (y - a.y())) / n.z();
    hits.push_back({std::clamp(z, z0, z1), int(geom), n.z() / len});
  }
  std::sort(hits.begin(), hits.end(),
            [](const ColumnHit& u, const ColumnHit& v) { return u.z < v.z || (u.z == v.z && u.mesh < v.mesh); });
  // A line through an edge shared by two faces of a mesh hits both: count such a crossing once
  // (same mesh, same direction, same height). Opposite directions (a grazed fold) both stay.
  std::vector<ColumnHit> out;
  out.reserve(hits.size());
  for (const auto& h : hits) {
    bool duplicate = false;
    for (auto it = out.rbegin(); it != out.rend() && h.z - it->z < 1e-7; ++it)
      if (it->mesh == h.mesh && (it->nz > 0) == (h.nz > 0)) duplicate = true;
    if (!duplicate) out.push_back(h);
  }
  return out;
}

void InsideTracker::cross(const ColumnHit& h) {
  const auto m = std::size_t(h.mesh);
  if (!closed_[m]) return;
  const bool was = winding_[m] != 0;
  winding_[m] += h.nz < 0 ? 1 : -1;  // facing down: the upward line enters an outward-facing mesh
  touched_.push_back(h.mesh);
  const bool is = winding_[m] != 0;
  inside_count_ += int(is) - int(was);
}

void InsideTracker::reset() {
  for (int m : touched_) winding_[std::size_t(m)] = 0;
  touched_.clear();
  inside_count_ = 0;
}

}  // namespace dmgplace::tools
