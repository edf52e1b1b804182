// Objects from scans against known truth: a procedural mesh ray-cast from a few viewpoints with
// 1 mm Gaussian noise (tools::synthetic_scan), written as PCD, baked, compared with the mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/geometry/procedural_meshes.hpp"
#include "dmgplace/tools/io/pcd_writer.hpp"
#include "dmgplace/tools/object/dmg_builder.hpp"
#include "dmgplace/tools/object/gripper_model.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"
#include "dmgplace/tools/object/placement_faces.hpp"
#include "dmgplace/tools/scan/scan_object.hpp"
#include "dmgplace/tools/scan/synthetic_scan.hpp"
#include "test_support.hpp"

namespace dmgplace::tools {
namespace {

TriMesh merged(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.vertices.resize(a.vertices.rows() + b.vertices.rows(), 3);
  m.vertices << a.vertices, b.vertices;
  m.triangles.resize(a.triangles.rows() + b.triangles.rows(), 3);
  m.triangles << a.triangles, (b.triangles.array() + int(a.vertices.rows())).matrix();
  return m;
}

TriMesh moved(TriMesh m, const Eigen::Vector3d& by) {
  m.vertices.rowwise() += by.transpose();
  return m;
}

// Scans of `object` (resting on a table when `table`) from `views` eyes at 0.5 m, azimuths spread
// round, at the given elevations (rad); one PCD per view with its viewpoint.
std::vector<std::filesystem::path> scan_files(const test::TempDir& dir, const TriMesh& object, bool table,
                                              const std::vector<double>& elevations) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < object.vertices.rows(); ++i) box.extend(object.vertices.row(i).transpose());
  TriMesh scene = object;
  if (table)
    scene = merged(object, moved(make_box_mesh({0.6, 0.6, 0.02}), Eigen::Vector3d(0, 0, box.min().z() - 0.01)));
  std::vector<std::filesystem::path> files;
  for (std::size_t v = 0; v < elevations.size(); ++v) {
    const double az = 2 * std::numbers::pi * double(v) / double(elevations.size()) + 0.3;
    const Eigen::Vector3d eye =
        box.center() + 0.5 * Eigen::Vector3d(std::cos(az) * std::cos(elevations[v]),
                                             std::sin(az) * std::cos(elevations[v]), std::sin(elevations[v]));
    SyntheticScanOptions so;
    so.seed = 7 + v;
    so.angular_step = 0.0015;
    const auto scan = synthetic_scan(scene, eye, box.center(), so);
    files.push_back(dir / ("view" + std::to_string(v) + ".pcd"));
    write_pcd(files.back(), scan.points, scan.viewpoint, scan.orientation);
  }
  return files;
}

struct Baked {
  formats::MassProperties mass;
  formats::PlacementFaces faces;
  formats::Dmg dmg;
};

Baked bake(const TriMesh& mesh) {
  Baked b;
  b.mass = compute_mass_properties(mesh, 0, "test");
  b.faces = compute_placement_faces(mesh, b.mass.com, {}, "test");
  b.dmg = build_dmg(mesh, default_gripper(), {}, "test");
  return b;
}

// Every stable face of `a` has one in `b` whose normal is within `deg` degrees.
bool faces_covered(const formats::PlacementFaces& a, const formats::PlacementFaces& b, double deg) {
  for (const auto& f : a.faces) {
    bool found = false;
    for (const auto& g : b.faces) found = found || f.normal.dot(g.normal) >= std::cos(deg * std::numbers::pi / 180);
    if (!found) return false;
  }
  return true;
}

void expect_like_truth(const TriMesh& truth_mesh, const ScanObject& scan, bool dmg_from_points = false) {
  const Baked truth = bake(truth_mesh);
  Baked got = bake(scan.mesh);
  if (dmg_from_points)
    got.dmg = build_dmg_from_points(scan.mesh, scan.points, scan.normals, default_gripper(), {}, "scan");
  std::printf(
      "[ measured ] volume %.3f of the truth, %zu / %zu stable faces, %zu / %zu DMG nodes, %.0f%% of the surface "
      "seen\n",
      got.mass.volume / truth.mass.volume, got.faces.faces.size(), truth.faces.faces.size(), got.dmg.nodes.size(),
      truth.dmg.nodes.size(), 100 * scan.reconstruction.seen_fraction);
  EXPECT_NEAR(got.mass.volume / truth.mass.volume, 1.0, 0.10)
      << "volume " << got.mass.volume << " vs " << truth.mass.volume;
  EXPECT_FALSE(truth.faces.faces.empty());
  EXPECT_TRUE(faces_covered(truth.faces, got.faces, 10)) << "a true stable face is missing";
  EXPECT_TRUE(faces_covered(got.faces, truth.faces, 10)) << "a stable face that the object does not have";
  const double nodes = double(got.dmg.nodes.size()), truth_nodes = double(truth.dmg.nodes.size());
  EXPECT_GT(truth_nodes, 0);
  EXPECT_LE(nodes, 2 * truth_nodes) << nodes << " nodes vs " << truth_nodes;
  EXPECT_GE(nodes, 0.5 * truth_nodes) << nodes << " nodes vs " << truth_nodes;
}

const TriMesh& box_truth() {
  static const TriMesh m = moved(make_box_mesh({0.05, 0.04, 0.09}), Eigen::Vector3d(0.01, -0.02, 0.045));
  return m;
}

// The box on a table, scanned from three sides above, its surface the hull of the points.
ScanObject box_on_a_table_by_hull(const test::TempDir& dir) {
  ScanObjectOptions o;
  o.reconstruct.method = Reconstruction::Hull;
  return object_from_scans(scan_files(dir, box_truth(), true, {0.6, 0.6, 0.6}), o);
}

TEST(ScanObject, ABoxOnATableScannedFromThreeSidesBakesLikeItsMesh) {
  test::TempDir dir;
  const auto scan = box_on_a_table_by_hull(dir);
  EXPECT_TRUE(scan.segmented.plane_removed);
  EXPECT_EQ(scan.segmented.clusters.size(), 1u);
  EXPECT_EQ(scan.segmented.orientation, "viewpoint");
  // Normals face out of the box: away from its center.
  const Eigen::Vector3d center(0.01, -0.02, 0.045);
  std::size_t outward = 0;
  for (std::size_t i = 0; i < scan.segmented.points.size(); ++i)
    outward += scan.segmented.normals[i].dot(scan.segmented.points[i] - center) > 0;
  EXPECT_GT(double(outward), 0.98 * double(scan.segmented.points.size()));
  // The object frame is the scan frame moved to the surface's box center: truth moved the same way.
  expect_like_truth(moved(box_truth(), -scan.origin_in_scan), scan);
  EXPECT_GT(scan.reconstruction.seen_fraction, 0.5);
}

TEST(ScanObject, PoissonRebuildsABoxSeenFromAboveAndBelow) {
  test::TempDir dir;
  const TriMesh& truth = box_truth();
  const auto files = scan_files(dir, truth, false, {0.6, 0.6, -0.6});
  ScanObjectOptions o;  // Poisson, the default
  const auto scan = object_from_scans(files, o);
  EXPECT_TRUE(scan.reconstruction.mesh.closed_manifold());
  expect_like_truth(moved(truth, -scan.origin_in_scan), scan);
}

TEST(ScanObject, TheOriginalsSupervoxelDmgIsOfComparableSize) {
  test::TempDir dir;
  const auto scan = box_on_a_table_by_hull(dir);
  expect_like_truth(moved(box_truth(), -scan.origin_in_scan), scan, true);
}

TEST(ScanObject, SeveralClustersNeedAChoiceAndTheErrorListsThem) {
  test::TempDir dir;
  const TriMesh two = merged(box_truth(), moved(make_box_mesh({0.04, 0.04, 0.04}), Eigen::Vector3d(0.15, 0.1, 0.02)));
  const auto files = scan_files(dir, two, true, {0.6, 0.6});
  ScanObjectOptions o;
  o.reconstruct.method = Reconstruction::Hull;
  const std::string e = test::error_of([&] { object_from_scans(files, o); });
  EXPECT_NE(e.find("2 clusters"), std::string::npos) << e;
  EXPECT_NE(e.find("--cluster"), std::string::npos) << e;
  o.segment.cluster_near = Eigen::Vector3d(0.15, 0.1, 0.02);
  const auto small = object_from_scans(files, o);
  o.segment.cluster_near.reset();
  o.segment.cluster = 0;
  const auto large = object_from_scans(files, o);
  EXPECT_LT(small.points.size(), large.points.size());
  EXPECT_NEAR(small.origin_in_scan.x(), 0.15, 0.01);
}

TEST(ScanObject, AFlatOrEmptyCropIsRefusedNamingTheFile) {
  test::TempDir dir;
  const auto files = scan_files(dir, box_truth(), true, {0.6});
  ScanObjectOptions o;
  o.segment.crop = Eigen::AlignedBox3d(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6));
  const std::string e = test::error_of([&] { object_from_scans(files, o); });
  EXPECT_NE(e.find("view0.pcd"), std::string::npos) << e;
  EXPECT_NE(e.find("--crop"), std::string::npos) << e;
}

}  // namespace
}  // namespace dmgplace::tools
