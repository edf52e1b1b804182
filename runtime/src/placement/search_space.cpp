#include "dmgplace/runtime/placement/search_space.hpp"

#include <cmath>

namespace dmgplace::runtime {

SearchSpace::SearchSpace(const formats::ObjectArtifact& object, const std::vector<formats::PlacementRegion>& regions,
                         const Eigen::AlignedBox3d& volume)
    : faces_(&object.placement), com_(object.mass.com) {
  for (std::size_t r = 0; r < regions.size(); ++r) {
    formats::PlacementRegion reg = regions[r];
    // A region belongs to the volume when its surface lies within V's height range (1 mm slack)...
    if (reg.height < volume.min().z() - 1e-3 || reg.height > volume.max().z()) continue;
    std::size_t kept = 0;
    for (int j = 0; j < reg.depth; ++j)
      for (int i = 0; i < reg.width; ++i) {
        // ... and only its cells whose centers are inside V's footprint are used.
        const std::size_t k = std::size_t(i) + std::size_t(reg.width) * std::size_t(j);
        const Eigen::Vector2d c = reg.cell_center(i, j);
        const bool in = c.x() >= volume.min().x() && c.x() <= volume.max().x() && c.y() >= volume.min().y() &&
                        c.y() <= volume.max().y();
        if (!in) reg.mask[k] = 0;
        kept += reg.mask[k] != 0;
      }
    if (kept == 0) continue;
    std::vector<int> pre(std::size_t(reg.width + 1) * std::size_t(reg.depth + 1), 0);
    auto at = [&](int i, int j) -> int& { return pre[std::size_t(i) + std::size_t(reg.width + 1) * std::size_t(j)]; };
    for (int j = 0; j < reg.depth; ++j)
      for (int i = 0; i < reg.width; ++i)
        at(i + 1, j + 1) = at(i, j + 1) + at(i + 1, j) - at(i, j) +
                           (reg.mask[std::size_t(i) + std::size_t(reg.width) * std::size_t(j)] != 0);
    regions_.push_back(std::move(reg));
    source_.push_back(int(r));
    prefix_.push_back(std::move(pre));
  }
}

CellRange SearchSpace::full_range(int r) const { return {0, region(r).width, 0, region(r).depth}; }

int SearchSpace::supported_cells(int r, const CellRange& c) const {
  const auto& pre = prefix_[std::size_t(r)];
  const std::size_t w = std::size_t(region(r).width + 1);
  auto at = [&](int i, int j) { return pre[std::size_t(i) + w * std::size_t(j)]; };
  return at(c.i1, c.j1) - at(c.i0, c.j1) - at(c.i1, c.j0) + at(c.i0, c.j0);
}

bool SearchSpace::supported(int r, const Eigen::Vector2d& xy) const {
  const auto& reg = region(r);
  const Eigen::Vector2d u = (xy - reg.origin) / reg.resolution;
  if (!(u.x() >= 0 && u.y() >= 0)) return false;  // NaN included
  const int i = int(u.x()), j = int(u.y());
  if (i >= reg.width || j >= reg.depth) return false;
  return reg.mask[std::size_t(i) + std::size_t(reg.width) * std::size_t(j)] != 0;
}

Eigen::Isometry3d SearchSpace::pose(int f, int r, const Eigen::Vector2d& xy, double theta) const {
  const auto& fc = face(f);
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.linear() = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix() * fc.rotation.toRotationMatrix();
  const Eigen::Vector3d com = x.linear() * com_;
  x.translation() = Eigen::Vector3d(xy.x() - com.x(), xy.y() - com.y(), region(r).height + fc.height);
  return x;
}

bool SearchSpace::stable(int f, int r, const Eigen::Isometry3d& x) const {
  const auto& poly = face(f).polygon;
  if (!supported(r, (x * com_).head<2>())) return false;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Eigen::Vector3d a = x * poly[k], b = x * poly[(k + 1) % poly.size()];
    if (!supported(r, a.head<2>()) || !supported(r, (0.5 * (a + b)).head<2>())) return false;
  }
  return true;
}

}  // namespace dmgplace::runtime
