#include "dmgplace/runtime/placement/placement_tree.hpp"

#include <cmath>
#include <numbers>

namespace dmgplace::runtime {

PlacementTree::PlacementTree(const SearchSpace& space, int max_depth, double c)
    : space_(&space), max_depth_(std::max(1, max_depth)), c_(c) {
  Node root;
  root.cell.t0 = 0;
  root.cell.t1 = 2 * std::numbers::pi;
  nodes_.push_back(root);
}

std::vector<PlacementTree::Cell> PlacementTree::list_children(const Cell& c) const {
  std::vector<Cell> out;
  if (leaf(c)) return out;
  if (c.level == 0) {
    for (int f = 0; f < space_->face_count(); ++f) {
      Cell k = c;
      k.level = 1;
      k.face = f;
      out.push_back(k);
    }
    return space_->region_count() > 0 ? out : std::vector<Cell>{};
  }
  if (c.level == 1) {
    for (int r = 0; r < space_->region_count(); ++r) {
      Cell k = c;
      k.level = 2;
      k.region = r;
      k.cells = space_->full_range(r);
      out.push_back(k);
    }
    return out;
  }
  // Halve each cell axis that is longer than one cell; quarter the rotation interval.
  const CellRange& r = c.cells;
  const int im = r.width() > 1 ? r.i0 + r.width() / 2 : r.i1;
  const int jm = r.depth() > 1 ? r.j0 + r.depth() / 2 : r.j1;
  std::vector<CellRange> parts;
  for (auto [i0, i1] : {std::pair{r.i0, im}, std::pair{im, r.i1}})
    for (auto [j0, j1] : {std::pair{r.j0, jm}, std::pair{jm, r.j1}}) {
      CellRange p{i0, i1, j0, j1};
      if (p.width() > 0 && p.depth() > 0 && space_->supported_cells(c.region, p) > 0) parts.push_back(p);
    }
  const double dt = (c.t1 - c.t0) / 4;
  for (const auto& p : parts)
    for (int t = 0; t < 4; ++t) {
      Cell k = c;
      k.level = c.level + 1;
      k.cells = p;
      k.t0 = c.t0 + t * dt;
      k.t1 = k.t0 + dt;
      out.push_back(k);
    }
  return out;
}

void PlacementTree::list(int n) {
  if (nodes_[std::size_t(n)].listed) return;
  nodes_[std::size_t(n)].unexpanded = list_children(nodes_[std::size_t(n)].cell);
  nodes_[std::size_t(n)].listed = true;
}

double PlacementTree::ucb(const Node& child, double log_parent) const {
  if (child.visits == 0) return std::numeric_limits<double>::infinity();
  return child.reward / child.visits + c_ * std::sqrt(2 * log_parent / child.visits);
}

int PlacementTree::select(std::mt19937_64& rng) {
  int n = 0;
  while (true) {
    list(n);
    Node& node = nodes_[std::size_t(n)];
    if (leaf(node.cell)) return n;
    const double log_n = std::log(std::max(1, node.visits));
    int best = -1;
    double best_ucb = -std::numeric_limits<double>::infinity(), mean = 0;
    for (int ch : node.children) {
      const double u = ucb(nodes_[std::size_t(ch)], log_n);
      const Node& cn = nodes_[std::size_t(ch)];
      mean += cn.visits ? cn.reward / cn.visits : 0;
      if (u > best_ucb) best_ucb = u, best = ch;
    }
    // Expand when nothing is expanded yet, or when an unseen child (credited with the children's
    // mean reward) would be selected: mean + c sqrt(2 ln N / |children|) >= the best UCB.
    bool expand = !node.unexpanded.empty();
    if (expand && !node.children.empty()) {
      mean /= double(node.children.size());
      expand = mean + c_ * std::sqrt(2 * log_n / double(node.children.size())) >= best_ucb;
    }
    if (expand) {
      std::uniform_int_distribution<std::size_t> pick(0, node.unexpanded.size() - 1);
      const std::size_t k = pick(rng);
      Node child;
      child.cell = node.unexpanded[k];
      child.parent = n;
      node.unexpanded.erase(node.unexpanded.begin() + std::ptrdiff_t(k));
      const int id = int(nodes_.size());
      nodes_[std::size_t(n)].children.push_back(id);
      nodes_.push_back(std::move(child));
      return id;
    }
    if (best < 0) return -1;  // a dead end: no children at all
    n = best;
  }
}

PlacementSample PlacementTree::rollout(int n, std::mt19937_64& rng) {
  Cell c = nodes_[std::size_t(n)].cell;
  while (!leaf(c)) {
    auto kids = list_children(c);
    if (kids.empty()) break;
    std::uniform_int_distribution<std::size_t> pick(0, kids.size() - 1);
    c = kids[pick(rng)];
  }
  PlacementSample s;
  s.node = n;
  s.face = c.face;
  s.region = c.region;
  if (s.face < 0 || s.region < 0) return s;
  // A supported cell of the leaf's range, uniformly, then a point in it and an angle.
  const int count = space_->supported_cells(c.region, c.cells);
  std::uniform_int_distribution<int> pick(0, std::max(0, count - 1));
  int k = pick(rng);
  const auto& reg = space_->region(c.region);
  for (int j = c.cells.j0; j < c.cells.j1; ++j)
    for (int i = c.cells.i0; i < c.cells.i1; ++i)
      if (reg.mask[std::size_t(i) + std::size_t(reg.width) * std::size_t(j)] && k-- == 0) {
        std::uniform_real_distribution<double> u(0, 1);
        s.xy = reg.origin + reg.resolution * Eigen::Vector2d(i + u(rng), j + u(rng));
      }
  std::uniform_real_distribution<double> t(c.t0, c.t1);
  s.theta = t(rng);
  s.pose = space_->pose(s.face, s.region, s.xy, s.theta);
  return s;
}

void PlacementTree::backpropagate(int n, double reward) {
  for (; n >= 0; n = nodes_[std::size_t(n)].parent) {
    ++nodes_[std::size_t(n)].visits;
    nodes_[std::size_t(n)].reward += reward;
  }
}

}  // namespace dmgplace::runtime
