#pragma once
// The placement hierarchy searched by MCTS (the paper's Algorithm 2): root -> stable face ->
// region -> recursive split of the region's cells (quadtree in x, y) paired with a 4-way split of
// the rotation interval, `max_depth` levels deep. Nodes are created as MCTS expands them; a
// rollout descends at random below the selected node and samples a pose in the leaf it reaches.
// Algorithm 3's grasp cache is keyed by these nodes but lives in GraspSelector.
#include <random>
#include <vector>

#include "dmgplace/runtime/placement/search_space.hpp"

namespace dmgplace::runtime {

struct PlacementSample {
  int node = -1;  // the tree node the rollout started from
  int face = -1, region = -1;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  // COM position on the region
  double theta = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // resting pose
};

class PlacementTree {
 public:
  struct Cell {
    int face = -1, region = -1;  // -1 above their level
    CellRange cells;
    double t0 = 0, t1 = 0;  // rotation interval
    int level = 0;          // 0 root, 1 face, 2 region, 3 .. 2 + max_depth cells
  };
  struct Node {
    Cell cell;
    int parent = -1;
    std::vector<int> children;
    std::vector<Cell> unexpanded;  // listed on first visit
    bool listed = false;
    int visits = 0;
    double reward = 0;  // sum
  };

  PlacementTree(const SearchSpace& space, int max_depth, double c);

  // UCB1 descent; expands one new child when the expansion rule says so. -1 when nothing is left.
  int select(std::mt19937_64& rng);
  PlacementSample rollout(int node, std::mt19937_64& rng);
  void backpropagate(int node, double reward);

  const Node& node(int n) const { return nodes_[std::size_t(n)]; }
  int size() const { return int(nodes_.size()); }
  bool leaf(const Cell& c) const { return c.level >= 2 + max_depth_; }

 private:
  std::vector<Cell> list_children(const Cell& c) const;
  void list(int n);
  double ucb(const Node& child, double log_parent) const;
  const SearchSpace* space_;
  int max_depth_;
  double c_;
  std::vector<Node> nodes_;
};

}  // namespace dmgplace::runtime
