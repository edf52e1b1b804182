#include "dmgplace/formats/winding_number.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using dmgplace::formats::RowMatrixX3d;
using dmgplace::formats::RowMatrixX3i;
using dmgplace::formats::TriMesh;
using dmgplace::formats::winding_number;

namespace {
// The textbook sum: every triangle's solid angle by its own atan2.
double winding_by_atan2(const TriMesh& m, const Eigen::Vector3d& p) {
  double total = 0;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.vertices.row(m.triangles(t, 0)).transpose() - p;
    const Eigen::Vector3d b = m.vertices.row(m.triangles(t, 1)).transpose() - p;
    const Eigen::Vector3d c = m.vertices.row(m.triangles(t, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return total / (4 * M_PI);
}

// A box [-1, 1]^3 with outward counter-clockwise faces, its corners moved by up to `jitter`.
TriMesh box(double jitter, std::mt19937& rng) {
  TriMesh m;
  m.vertices.resize(8, 3);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  for (int i = 0; i < 8; ++i)
    m.vertices.row(i) << (i & 1 ? 1 : -1) + u(rng), (i & 2 ? 1 : -1) + u(rng), (i & 4 ? 1 : -1) + u(rng);
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3,
      7, 5;
  return m;
}

// The mesh's triangles `times` over (a solid wound several times).
TriMesh repeated(const TriMesh& m, int times) {
  TriMesh out;
  out.vertices = m.vertices;
  out.triangles.resize(m.triangles.rows() * times, 3);
  for (int k = 0; k < times; ++k) out.triangles.middleRows(k * m.triangles.rows(), m.triangles.rows()) = m.triangles;
  return out;
}
}  // namespace

TEST(WindingNumber, AgreesWithTheSumOfAtan2sOnClosedOpenInvertedAndRepeatedMeshes) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  for (int trial = 0; trial < 20; ++trial) {
    const TriMesh closed = box(0.3, rng);
    TriMesh open = closed;
    open.triangles.conservativeResize(10, 3);  // two faces short: a hole
    TriMesh inverted = closed;
    inverted.triangles.col(1).swap(inverted.triangles.col(2));
    for (const TriMesh* m : std::initializer_list<const TriMesh*>{&closed, &open, &inverted}) {
      for (int times : {1, 3}) {
        const TriMesh mesh = repeated(*m, times);
        for (int k = 0; k < 200; ++k) {
          const Eigen::Vector3d p(u(rng), u(rng), u(rng));
          EXPECT_NEAR(winding_number(mesh, p), winding_by_atan2(mesh, p), 1e-9)
              << "trial " << trial << " at " << p.transpose();
        }
      }
    }
  }
}

TEST(WindingNumber, IsTheIntegerCountOffTheSurfaceOfAClosedMesh) {
  std::mt19937 rng(5);
  const TriMesh cube = box(0.0, rng);
  // Points on a grid through the faces' planes, their edges and corners, inside and out: the
  // turn counting must stay exact where a triangle's angle is 0 or pi.
  for (int times : {1, 2}) {
    const TriMesh mesh = repeated(cube, times);
    for (double x = -1.5; x <= 1.5; x += 0.5)
      for (double y = -1.5; y <= 1.5; y += 0.5)
        for (double z = -1.5; z <= 1.5; z += 0.5) {
          const Eigen::Vector3d p(x, y, z);
          const double w = winding_number(mesh, p);
          ASSERT_TRUE(std::isfinite(w));
          const bool inside = std::abs(x) < 1 && std::abs(y) < 1 && std::abs(z) < 1;
          const bool outside = std::abs(x) > 1 || std::abs(y) > 1 || std::abs(z) > 1;
          if (inside) {
            EXPECT_NEAR(w, times, 1e-9) << p.transpose();
          } else if (outside) {
            EXPECT_NEAR(w, 0, 1e-9) << p.transpose();
          }
          // On the surface the textbook sum reads a -0 angle as -pi where this reads +pi: the same
          // up to whole turns.
          if (!inside && !outside) {
            EXPECT_NEAR(std::remainder(w - winding_by_atan2(mesh, p), 1.0), 0.0, 1e-9) << p.transpose();
          }
        }
  }
}

TEST(WindingNumber, APointOnTwoCoincidentTrianglesIsHalfATurnFromEach) {
  // Each triangle's angle is pi: the second turn lands on the positive axis, a whole turn.
  TriMesh m;
  m.vertices.resize(3, 3);
  m.vertices << -1, -1, 0, 2, -1, 0, -1, 2, 0;
  m.triangles.resize(2, 3);
  m.triangles << 0, 1, 2, 0, 1, 2;
  EXPECT_NEAR(winding_number(m, Eigen::Vector3d(0, 0, 0)), 1.0, 1e-12);
  m.triangles.conservativeResize(1, 3);
  EXPECT_NEAR(winding_number(m, Eigen::Vector3d(0, 0, 0)), 0.5, 1e-12);
}
