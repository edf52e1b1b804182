// Placement faces on analytic shapes: counts, stability, and the stored geometry's invariants.
#include "dmgplace/tools/object/placement_faces.hpp"

#include <gtest/gtest.h>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/geometry/procedural_meshes.hpp"
#include "dmgplace/tools/object/mass_properties.hpp"

namespace dmgplace::tools {
namespace {

formats::PlacementFaces faces_of(const TriMesh& m, const FaceOptions& o = {}) {
  const auto mass = compute_mass_properties(m, 0, "test");
  return compute_placement_faces(m, mass.com, o, "test");
}

TEST(PlacementFaces, ABoxHasSixFacesWithCorrectGeometry) {
  const Eigen::Vector3d ext(0.1, 0.06, 0.04);
  const auto p = faces_of(make_box_mesh(ext));
  ASSERT_EQ(p.faces.size(), 6u);
  for (const auto& f : p.faces) {
    int axis = 0;
    EXPECT_NEAR(f.normal.cwiseAbs().maxCoeff(&axis), 1.0, 1e-12);
    EXPECT_NEAR(f.height, 0.5 * ext[axis], 1e-12);
    EXPECT_EQ(f.polygon.size(), 4u);
    // The box's COM is its center: the margin is half the smaller in-plane extent.
    const double other_a = ext[(axis + 1) % 3], other_b = ext[(axis + 2) % 3];
    EXPECT_NEAR(f.margin, 0.5 * std::min(other_a, other_b), 1e-12);
    EXPECT_LT((f.rotation * f.normal - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  }
}

TEST(PlacementFaces, BottleStandsOnItsBottomAndLiesOnItsSide) {
  const auto p = faces_of(make_bottle_mesh());
  bool bottom = false;
  int side = 0;
  for (const auto& f : p.faces) {
    if (f.normal.z() < -0.999) bottom = true;
    if (std::abs(f.normal.z()) < 0.2) ++side;
  }
  EXPECT_TRUE(bottom);
  EXPECT_GE(side, 8);  // side facets all round (merged in groups, 32 segments)
}

TEST(PlacementFaces, AComOverrideThatTipsAFaceRemovesIt) {
  const auto box = make_box_mesh({0.1, 0.1, 0.1});
  FaceOptions o;
  const auto centered = compute_placement_faces(box, Eigen::Vector3d::Zero(), o, "test");
  ASSERT_EQ(centered.faces.size(), 6u);
  // COM 4.5 cm off center along +x: inside the box, but less than 1 cm from the +x side's edges,
  // so every face except -x and +x tips over (and +x keeps it at its center line).
  const auto shifted = compute_placement_faces(box, Eigen::Vector3d(0.045, 0, 0), o, "test");
  EXPECT_EQ(shifted.faces.size(), 2u);
  for (const auto& f : shifted.faces) EXPECT_NEAR(std::abs(f.normal.x()), 1.0, 1e-12);
}

TEST(PlacementFaces, FlatMeshIsRejected) {
  TriMesh flat;
  flat.vertices.resize(3, 3);
  flat.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  flat.triangles.resize(1, 3);
  flat.triangles << 0, 1, 2;
  EXPECT_THROW(compute_placement_faces(flat, Eigen::Vector3d::Zero(), {}, "flat.stl"), Error);
}

}  // namespace
}  // namespace dmgplace::tools
