#pragma once
// Single-source shortest paths on a sparse graph with non-negative costs (Dijkstra, binary heap).
#include <span>
#include <vector>

namespace dmgplace::runtime {

// Compressed adjacency: the edges leaving vertex v are [offsets[v], offsets[v + 1]).
struct WeightedGraph {
  std::vector<int> offsets{0};
  std::vector<int> targets;
  std::vector<double> costs;  // >= 0
  int size() const { return int(offsets.size()) - 1; }
  // Builds the compressed form from an edge list (from, to, cost); order within a vertex is kept.
  static WeightedGraph from_edges(int vertices, const std::vector<std::tuple<int, int, double>>& edges);
};

struct ShortestPaths {
  std::vector<double> cost;      // +inf when unreachable
  std::vector<int> predecessor;  // -1 for the source and unreachable vertices
  std::vector<int> via_edge;     // index into targets/costs of the edge used, -1 likewise
};

// O((V + E) log V). Throws std::out_of_range for a source outside the graph.
ShortestPaths dijkstra(const WeightedGraph& g, int source);

}  // namespace dmgplace::runtime
