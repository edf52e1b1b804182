#include "dmgplace/runtime/geometry/convex_gap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::runtime {

ConvexSolid ConvexSolid::box(const Eigen::Vector3d& half) {
  ConvexSolid s;
  s.kind_ = Kind::Box;
  s.size_ = half.cwiseAbs();
  s.radius_ = s.size_.norm();
  return s;
}

ConvexSolid ConvexSolid::cylinder(double radius, double half_length) {
  ConvexSolid s;
  s.kind_ = Kind::Cylinder;
  s.size_ = Eigen::Vector3d(std::abs(radius), std::abs(half_length), 0);
  s.radius_ = std::hypot(radius, half_length);
  return s;
}

ConvexSolid ConvexSolid::sphere(double radius) {
  ConvexSolid s;
  s.kind_ = Kind::Sphere;
  s.size_ = Eigen::Vector3d(std::abs(radius), 0, 0);
  s.radius_ = std::abs(radius);
  return s;
}

ConvexSolid ConvexSolid::hull(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) throw Error("ConvexSolid", "hull", "no points");
  ConvexSolid s;
  s.kind_ = Kind::Hull;
  Eigen::AlignedBox3d box;
  for (const auto& p : points) {
    s.x_.push_back(p.x());
    s.y_.push_back(p.y());
    s.z_.push_back(p.z());
    box.extend(p);
  }
  s.center_ = box.center();
  for (const auto& p : points) s.radius_ = std::max(s.radius_, (p - s.center_).norm());
  return s;
}

ConvexSolid ConvexSolid::hull(const std::vector<Eigen::Vector3d>& points,
                              const std::vector<Eigen::Vector3i>& triangles) {
  ConvexSolid s = hull(points);
  const int n = int(points.size());
  std::vector<std::vector<int>> around(points.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a < 0 || a >= n || b < 0 || b >= n) throw Error("ConvexSolid", "hull", "vertex index out of range");
      around[std::size_t(a)].push_back(b);
      around[std::size_t(b)].push_back(a);
    }
  s.first_.push_back(0);
  for (auto& v : around) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    s.adjacent_.insert(s.adjacent_.end(), v.begin(), v.end());
    s.first_.push_back(int(s.adjacent_.size()));
  }
  // Climbs start from the best of the vertices farthest along the axes and the diagonals.
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        if ((x == 0 && y == 0 && z == 0) || std::abs(x) + std::abs(y) + std::abs(z) == 2) continue;
        int at = 0;
        s.scan(Eigen::Vector3d(x, y, z), at);
        if (std::find(s.seeds_.begin(), s.seeds_.end(), at) == s.seeds_.end()) s.seeds_.push_back(at);
      }
  return s;
}

std::optional<ConvexSolid> ConvexSolid::of(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::Box:
      return box(shape.size / 2);
    case ShapeType::Cylinder:
      return cylinder(shape.size[0], shape.size[1] / 2);
    case ShapeType::Sphere:
      return sphere(shape.size[0]);
    case ShapeType::Mesh: {
      if (shape.hull.rows() == 0) return std::nullopt;
      std::vector<int> index(std::size_t(shape.mesh.vertices.rows()), -1);  // mesh vertex -> hull point
      std::vector<Eigen::Vector3d> points;
      std::vector<Eigen::Vector3i> triangles;
      for (Eigen::Index r = 0; r < shape.hull.rows(); ++r) {
        Eigen::Vector3i t;
        for (int k = 0; k < 3; ++k) {
          const int v = shape.hull(r, k);
          if (v < 0 || v >= shape.mesh.vertices.rows()) throw Error("ConvexSolid", "hull", "vertex index out of range");
          if (index[std::size_t(v)] < 0) {
            index[std::size_t(v)] = int(points.size());
            points.push_back(shape.mesh.vertices.row(v).transpose());
          }
          t[k] = index[std::size_t(v)];
        }
        triangles.push_back(t);
      }
      return hull(points, triangles);
    }
  }
  return std::nullopt;
}

Eigen::Vector3d ConvexSolid::support(const Eigen::Vector3d& d, int& start) const {
  switch (kind_) {
    case Kind::Box:
      return {std::copysign(size_.x(), d.x()), std::copysign(size_.y(), d.y()), std::copysign(size_.z(), d.z())};
    case Kind::Cylinder: {
      const double rho = std::hypot(d.x(), d.y());
      const double z = std::copysign(size_.y(), d.z());
      if (!(rho > 0)) return {0, 0, z};
      return {size_.x() * d.x() / rho, size_.x() * d.y() / rho, z};
    }
    case Kind::Sphere: {
      const double n = d.norm();
      return n > 0 ? Eigen::Vector3d(d * (size_.x() / n)) : Eigen::Vector3d(size_.x(), 0, 0);
    }
    case Kind::Hull: {
      if (first_.empty()) return scan(d, start);
      int at = start;
      if (at < 0 || at >= int(x_.size())) {
        at = seeds_[0];
        for (const int k : seeds_)
          if (along(k, d) > along(at, d)) at = k;
      }
      // Climb to a neighbour farther along d while there is one. On a convex surface a vertex no
      // neighbour beats is the farthest (the simplex method's argument); a near tie (a flat face
      // or edge across d, where the climb may stop on an inner vertex, or rounding) is settled
      // by the full scan instead.
      const double tie = 1e-10 * (center_.norm() + radius_) * d.lpNorm<1>();
      double value = along(at, d);
      for (std::size_t step = 0; step < x_.size(); ++step) {
        int next = -1;
        double next_value = value;
        bool tied = false;
        for (int e = first_[std::size_t(at)]; e < first_[std::size_t(at) + 1]; ++e) {
          const int nb = adjacent_[std::size_t(e)];
          const double v = along(nb, d);
          if (v > next_value) {
            next = nb;
            next_value = v;
          } else if (v > value - tie) {
            tied = true;
          }
        }
        if (next < 0) {
          if (tied) return scan(d, start);
          start = at;
          return {x_[std::size_t(at)], y_[std::size_t(at)], z_[std::size_t(at)]};
        }
        at = next;
        value = next_value;
      }
      return scan(d, start);
    }
  }
  return Eigen::Vector3d::Zero();
}

Eigen::Vector3d ConvexSolid::scan(const Eigen::Vector3d& d, int& at) const {
  double best = -std::numeric_limits<double>::infinity();
  at = 0;
  for (int i = 0; i < int(x_.size()); ++i) {
    const double v = along(i, d);
    if (v > best) {
      best = v;
      at = i;
    }
  }
  return {x_[std::size_t(at)], y_[std::size_t(at)], z_[std::size_t(at)]};
}

namespace {

// The point of the simplex closest to the origin; the simplex shrinks to the vertices that point
// needs. False when the origin is inside a tetrahedron (the solids overlap).
struct Simplex {
  Eigen::Vector3d p[4];
  int n = 0;
};

Eigen::Vector3d closest_on_segment(Simplex& s) {
  const Eigen::Vector3d &a = s.p[0], &b = s.p[1];
  const Eigen::Vector3d ab = b - a;
  const double den = ab.squaredNorm();
  const double t = den > 0 ? std::clamp(-a.dot(ab) / den, 0.0, 1.0) : 0.0;
  if (t <= 0) {
    s.n = 1;
    return a;
  }
  if (t >= 1) {
    s.p[0] = b;
    s.n = 1;
    return b;
  }
  return a + t * ab;
}

// Ericson, Real-Time Collision Detection 5.1.5, with the query point at the origin: as
// formats/triangle_distance.hpp, but also shrinking the simplex to the region's vertices (keeping
// all three instead stalls GJK short of the distance: ConvexGap's tightness test fails).
Eigen::Vector3d closest_on_triangle(Simplex& s) {
  const Eigen::Vector3d a = s.p[0], b = s.p[1], c = s.p[2];
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    s.n = 1;
    return a;
  }
  const Eigen::Vector3d bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    s.p[0] = b;
    s.n = 1;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    s.n = 2;
    return a + v * ab;
  }
  const Eigen::Vector3d cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    s.p[0] = c;
    s.n = 1;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    s.p[1] = c;
    s.n = 2;
    return a + w * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    s.p[0] = b;
    s.p[1] = c;
    s.n = 2;
    return b + w * (c - b);
  }
  const double sum = va + vb + vc;
  if (!(std::abs(sum) > 0)) {  // degenerate (collinear): the best of its edges
    Simplex e1{{a, b}, 2}, e2{{b, c}, 2}, e3{{a, c}, 2};
    const Eigen::Vector3d q1 = closest_on_segment(e1), q2 = closest_on_segment(e2), q3 = closest_on_segment(e3);
    const double n1 = q1.squaredNorm(), n2 = q2.squaredNorm(), n3 = q3.squaredNorm();
    if (n1 <= n2 && n1 <= n3) {
      s = e1;
      return q1;
    }
    if (n2 <= n3) {
      s = e2;
      return q2;
    }
    s = e3;
    return q3;
  }
  const double v = vb / sum, w = vc / sum;
  return a + v * ab + w * ac;
}

// The origin against each face seen from outside (the opposite vertex on the other side).
bool closest_on_tetrahedron(Simplex& s, Eigen::Vector3d& out) {
  static constexpr int kFace[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  double best = std::numeric_limits<double>::infinity();
  Simplex best_s;
  bool outside_any = false;
  for (const auto& f : kFace) {
    const Eigen::Vector3d &a = s.p[f[0]], &b = s.p[f[1]], &c = s.p[f[2]], &d = s.p[f[3]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double so = -a.dot(n), sd = (d - a).dot(n);
    if (!(so * sd < 0) && !(sd == 0)) continue;  // the origin is on d's side of this face
    outside_any = true;
    Simplex t{{a, b, c}, 3};
    const Eigen::Vector3d q = closest_on_triangle(t);
    if (q.squaredNorm() < best) {
      best = q.squaredNorm();
      best_s = t;
      out = q;
    }
  }
  if (!outside_any) return false;
  s = best_s;
  return true;
}

}  // namespace

double convex_gap(const ConvexSolid& a, const Eigen::Isometry3d& ta, const ConvexSolid& b, const Eigen::Isometry3d& tb,
                  double tolerance, double enough, GapHint* hint, Eigen::Vector3d* separation) {
  // What the returned bound gives up: rounding in the support arithmetic, and what a climb may
  // miss on a hull that is convex only to the artifact check's tolerance (1e-9 of its extent).
  const double slack = 1e-12 * (1 + a.radius() + b.radius()) + a.climb_slack() + b.climb_slack();
  // Support of A - B against direction v, in the world frame.
  int from_a = hint ? hint->from_a : -1,
      from_b = hint ? hint->from_b : -1;  // hull vertices of the last supports: the next climbs start there
  // (R p + t spelled out: Eigen multiplies an Isometry3d's whole 4x4 matrix into (p, 1).)
  auto support = [&](const Eigen::Vector3d& v) -> Eigen::Vector3d {
    const Eigen::Vector3d pa = a.support(ta.linear().transpose() * -v, from_a),
                          pb = b.support(tb.linear().transpose() * v, from_b);
    return (ta.linear() * pa + ta.translation()) - (tb.linear() * pb + tb.translation());
  };
  // A hinted start is a direction only: until the first support, v is no point of A - B, so its
  // length bounds nothing (the first tolerance test waits).
  const bool hinted = hint && hint->v.squaredNorm() > 1e-24 && hint->v.allFinite();
  Eigen::Vector3d v = hinted ? hint->v : Eigen::Vector3d(ta * a.center() - tb * b.center());
  if (!(v.squaredNorm() > 0)) v = Eigen::Vector3d::UnitX();
  double lower = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d best = Eigen::Vector3d::Zero();  // the direction of `lower`, unit
  Simplex s;
  for (int iter = 0; iter < 64; ++iter) {
    const double vn = v.norm();
    if (!(vn > 1e-12)) break;  // the origin is (nearly) in A - B
    const Eigen::Vector3d w = support(v);
    if (const double along = v.dot(w) / vn; along > lower) {
      lower = along;
      best = v / vn;
    }
    if ((iter > 0 || !hinted) && vn - lower <= tolerance) break;  // the bound is within tolerance of the estimate
    // Proven above `enough`. A sign query (enough <= 0) also stops once it never will be (past the
    // first v, between the centers, v is a point of A - B: the distance is at most vn); a
    // certificate asking for more goes on to the best bound it can get.
    if (enough < std::numeric_limits<double>::infinity() &&
        (lower - slack > enough || (enough <= 0 && iter > 0 && !(vn - slack > enough))))
      break;
    bool repeated = false;  // no new support point: no progress left
    for (int k = 0; k < s.n; ++k) repeated |= (s.p[k] - w).squaredNorm() <= 1e-24;
    if (repeated) break;
    s.p[s.n++] = w;
    Eigen::Vector3d next;
    if (s.n == 1) next = w;
    else if (s.n == 2) next = closest_on_segment(s);
    else if (s.n == 3) next = closest_on_triangle(s);
    else if (!closest_on_tetrahedron(s, next)) break;  // the origin is inside: lower <= 0 already
    // Rounding: no descent left (the first v, between the centers, is not a point of A - B).
    if (iter > 0 && !(next.squaredNorm() < v.squaredNorm())) break;
    v = next;
  }
  if (hint) {
    if (v.squaredNorm() > 1e-24 && v.allFinite()) hint->v = v;
    hint->from_a = from_a;
    hint->from_b = from_b;
  }
  if (separation) *separation = best;
  return lower - slack;  // the dual bound alone
}

}  // namespace dmgplace::runtime
