#include "dmgplace/runtime/grasp/reachable_grasps.hpp"

#include <algorithm>
#include <cmath>

namespace dmgplace::runtime {

ReachableGrasps reachable_grasps(const GraspGraph& g, const Eigen::Isometry3d& initial_tcp,
                                 std::optional<double> opening) {
  ReachableGrasps r;
  r.initial_state = g.snap(initial_tcp, opening, &r.snap_distance);
  if (r.initial_state < 0) return r;
  r.paths = dijkstra(g.graph(), r.initial_state);
  for (int s = 0; s < g.size(); ++s)
    if (std::isfinite(r.paths.cost[s])) r.grasps.push_back({s, g.tcp_pose(s), g.opening(s), r.paths.cost[s]});
  std::stable_sort(r.grasps.begin(), r.grasps.end(), [](const auto& a, const auto& b) { return a.cost < b.cost; });
  return r;
}

std::vector<InHandAction> ReachableGrasps::actions_to(const GraspGraph& g, int state) const {
  std::vector<int> chain;  // states from the initial one to `state`
  if (state < 0 || state >= int(paths.cost.size()) || !std::isfinite(paths.cost[state])) return {};
  for (int s = state; s >= 0; s = paths.predecessor[s]) chain.push_back(s);
  std::reverse(chain.begin(), chain.end());
  std::vector<InHandAction> out;
  for (std::size_t i = 1; i < chain.size(); ++i) {
    const int a = chain[i - 1], b = chain[i];
    const GraspMove m = g.move(paths.via_edge[b]);
    if (out.empty() || out.back().type != m) {
      InHandAction act;
      act.type = m;
      act.from_state = a;
      if (m == GraspMove::Translation) {
        act.finger1_path = {g.contact1(a)};
        act.finger2_path = {g.contact2(a)};
        act.push_direction = (g.contact1(b) - g.contact1(a)).normalized();
      } else {
        act.axis = g.dmg().nodes[g.state(a).node].normal;
        act.pivot = g.tcp_pose(a).translation();
      }
      out.push_back(act);
    }
    InHandAction& act = out.back();
    act.to_state = b;
    if (m == GraspMove::Translation) {
      act.distance += (g.contact1(b) - g.contact1(a)).norm();
      act.finger1_path.push_back(g.contact1(b));
      act.finger2_path.push_back(g.contact2(b));
    } else {
      const int k = g.dmg().angle_count();
      const int d = ((g.state(b).angle - g.state(a).angle) % k + k) % k;  // 1 or k - 1
      act.angle += (d == 1 ? 1 : -1) * g.angle_step();
    }
  }
  return out;
}

}  // namespace dmgplace::runtime
