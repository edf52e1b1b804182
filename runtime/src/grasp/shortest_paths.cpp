#include "dmgplace/runtime/grasp/shortest_paths.hpp"

#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace dmgplace::runtime {

WeightedGraph WeightedGraph::from_edges(int vertices, const std::vector<std::tuple<int, int, double>>& edges) {
  WeightedGraph g;
  g.offsets.assign(std::size_t(vertices) + 1, 0);
  for (const auto& [from, to, cost] : edges) ++g.offsets[std::size_t(from) + 1];
  for (int v = 0; v < vertices; ++v) g.offsets[v + 1] += g.offsets[v];
  g.targets.resize(edges.size());
  g.costs.resize(edges.size());
  std::vector<int> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (const auto& [from, to, cost] : edges) {
    g.targets[fill[from]] = to;
    g.costs[fill[from]++] = cost;
  }
  return g;
}

ShortestPaths dijkstra(const WeightedGraph& g, int source) {
  const int n = g.size();
  if (source < 0 || source >= n) throw std::out_of_range("dijkstra: source vertex out of range");
  ShortestPaths r;
  r.cost.assign(n, std::numeric_limits<double>::infinity());
  r.predecessor.assign(n, -1);
  r.via_edge.assign(n, -1);
  using Item = std::pair<double, int>;
  // Lazy deletion: a vertex may sit in the heap several times; stale entries are skipped.
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  r.cost[source] = 0;
  heap.push({0.0, source});
  while (!heap.empty()) {
    const auto [c, v] = heap.top();
    heap.pop();
    if (c > r.cost[v]) continue;
    for (int e = g.offsets[v]; e < g.offsets[v + 1]; ++e) {
      const int w = g.targets[e];
      const double nc = c + g.costs[e];
      if (nc < r.cost[w]) {
        r.cost[w] = nc;
        r.predecessor[w] = v;
        r.via_edge[w] = e;
        heap.push({nc, w});
      }
    }
  }
  return r;
}

}  // namespace dmgplace::runtime
