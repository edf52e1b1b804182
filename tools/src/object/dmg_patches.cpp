// Surface patches and facets of the DMG. Instead of PCL supervoxels on a point cloud we segment
// the mesh itself: cubic cells of the seed size cut by the mesh's creases, so that a patch never
// straddles a sharp edge (a supervoxel across a box edge gets a diagonal normal). See docs/dmg.md.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "dmg_internal.hpp"

namespace dmgplace::tools::detail {
namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
};

// Unordered pairs of labels whose samples lie within 2 spacings with normals on the same side.
std::vector<std::set<int>> label_adjacency(const SurfaceSamples& s, const SampleGrid& grid,
                                           const std::vector<int>& label, int labels) {
  std::vector<std::set<int>> adj(labels);
  for (std::size_t i = 0; i < s.position.size(); ++i)
    grid.near(s.position[i], 2 * s.spacing, [&](int j) {
      if (label[j] != label[i] && s.normal[i].dot(s.normal[j]) > 0) {
        adj[label[i]].insert(label[j]);
        adj[label[j]].insert(label[i]);
      }
    });
  return adj;
}

}  // namespace

Patches segment_patches(const TriMesh& mesh, const SurfaceSamples& s, const SampleGrid& grid, double seed,
                        double crease_angle) {
  const auto region = crease_regions(mesh, crease_angle);
  const std::size_t n = s.position.size();
  std::map<std::array<long, 4>, int> ids;
  std::vector<int> label(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = s.position[i];
    std::array<long, 4> key{long(std::floor(p.x() / seed)), long(std::floor(p.y() / seed)),
                            long(std::floor(p.z() / seed)), region[s.triangle[i]]};
    label[i] = ids.emplace(key, int(ids.size())).first->second;
  }
  const int cells = int(ids.size());
  std::vector<Eigen::Vector3d> nsum(cells, Eigen::Vector3d::Zero());
  std::vector<int> count(cells, 0);
  for (std::size_t i = 0; i < n; ++i) nsum[label[i]] += s.normal[i], ++count[label[i]];

  // Slivers that a cell boundary cut off join the neighbour whose normal agrees best.
  const double full = (seed / s.spacing) * (seed / s.spacing);
  const auto adj = label_adjacency(s, grid, label, cells);
  std::vector<int> order(cells);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return count[a] < count[b]; });
  UnionFind uf(cells);
  for (int c : order) {
    const int rc = uf.find(c);
    if (count[rc] >= 0.3 * full) continue;
    int best = -1;
    double best_dot = -2;
    for (int nb : adj[c]) {
      const int r = uf.find(nb);
      if (r == rc) continue;
      const double d = nsum[r].normalized().dot(nsum[rc].normalized());
      if (d > best_dot) best_dot = d, best = r;
    }
    if (best < 0 || best_dot < std::cos(crease_angle)) continue;
    uf.parent[rc] = best;
    nsum[best] += nsum[rc];
    count[best] += count[rc];
  }

  Patches out;
  std::vector<int> compact(cells, -1);
  out.of_sample.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int r = uf.find(label[i]);
    if (compact[r] < 0) compact[r] = int(out.size.size()), out.size.push_back(0);
    out.of_sample[i] = compact[r];
    ++out.size[compact[r]];
  }
  const std::size_t np = out.size.size();
  std::vector<Eigen::Vector3d> mean(np, Eigen::Vector3d::Zero());
  out.normal.assign(np, Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < n; ++i)
    mean[out.of_sample[i]] += s.position[i], out.normal[out.of_sample[i]] += s.normal[i];
  for (std::size_t p = 0; p < np; ++p) {
    mean[p] /= out.size[p];
    out.normal[p] = out.normal[p].norm() > 0 ? out.normal[p].normalized() : Eigen::Vector3d::UnitZ();
  }
  // The contact point is a sample (always on the surface): the patch's outermost along its normal,
  // where a flat pad pressed along -n touches first, ties (flat patches) broken towards the mean.
  std::vector<double> best(np, -std::numeric_limits<double>::infinity());
  out.position.assign(np, Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    const int p = out.of_sample[i];
    const double score = out.normal[p].dot(s.position[i]) - 0.02 * (s.position[i] - mean[p]).norm();
    if (score > best[p]) best[p] = score, out.position[p] = s.position[i];
  }
  const auto padj = label_adjacency(s, grid, out.of_sample, int(np));
  for (const auto& a : padj) out.neighbours.emplace_back(a.begin(), a.end());
  return out;
}

Facets find_facets(const Patches& p, double normal_threshold) {
  const std::size_t np = p.normal.size();
  UnionFind uf(np);
  for (std::size_t i = 0; i < np; ++i)
    for (int j : p.neighbours[i])
      if ((p.normal[i] - p.normal[j]).squaredNorm() < normal_threshold) uf.parent[uf.find(int(i))] = uf.find(j);
  Facets f;
  f.of_patch.resize(np);
  std::vector<int> compact(np, -1);
  for (std::size_t i = 0; i < np; ++i) {
    const int r = uf.find(int(i));
    if (compact[r] < 0) compact[r] = int(f.normal.size()), f.normal.emplace_back(), f.zero_axis.emplace_back();
    f.of_patch[i] = compact[r];
  }
  const std::size_t nf = f.normal.size();
  std::vector<Eigen::Vector3d> sum(nf, Eigen::Vector3d::Zero());
  std::vector<Eigen::Matrix3d> scatter(nf, Eigen::Matrix3d::Zero());
  std::vector<double> weight(nf, 0);
  for (std::size_t i = 0; i < np; ++i) {
    const int k = f.of_patch[i];
    sum[k] += p.size[i] * p.normal[i];
    scatter[k] += p.size[i] * p.normal[i] * p.normal[i].transpose();
    weight[k] += p.size[i];
  }
  for (std::size_t k = 0; k < nf; ++k) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter[k] / weight[k]);  // eigenvalues ascending
    // A closed band (a cylinder's side) has a near-zero mean normal: use its main direction then.
    const Eigen::Vector3d n =
        sum[k].norm() > 0.3 * weight[k] ? Eigen::Vector3d(sum[k].normalized()) : es.eigenvectors().col(2);
    // The zero-angle axis is the direction the normals vary least along (a cylinder's axis); on a
    // flat facet that is undefined, and the world axis least aligned with n is used instead.
    Eigen::Vector3d z = es.eigenvectors().col(0);
    if (es.eigenvalues()(1) < 0.05) {
      int axis = 0;
      n.cwiseAbs().minCoeff(&axis);
      z = Eigen::Vector3d::Unit(axis);
    }
    z -= n.dot(z) * n;
    if (z.norm() < 1e-6) z = n.unitOrthogonal();
    f.normal[k] = n;
    f.zero_axis[k] = z.normalized();
  }
  return f;
}

}  // namespace dmgplace::tools::detail
