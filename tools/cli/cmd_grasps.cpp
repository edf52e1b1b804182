// `dmgplace grasps OBJECT.h5 --initial POSE`: the grasps reachable in-hand from an initial grasp.
#include <cstdio>
#include "dmgplace/formats/pose_input.hpp"
#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/runtime/grasp/reachable_grasps.hpp"

namespace dmgplace::cli {
namespace {

nlohmann::ordered_json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::ordered_json pose(const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.linear());
  return {t.translation().x(), t.translation().y(), t.translation().z(), q.x(), q.y(), q.z(), q.w()};
}

nlohmann::ordered_json action_json(const runtime::InHandAction& a) {
  nlohmann::ordered_json j;
  if (a.type == runtime::GraspMove::Translation) {
    j["type"] = "translation";
    j["distance"] = a.distance;
    j["push_direction"] = vec(a.push_direction);
    for (const auto& p : a.finger1_path) j["finger1_path"].push_back(vec(p));
    for (const auto& p : a.finger2_path) j["finger2_path"].push_back(vec(p));
  } else {
    j["type"] = "rotation";
    j["angle"] = a.angle;
    j["axis"] = vec(a.axis);
    j["pivot"] = vec(a.pivot);
  }
  j["from_state"] = a.from_state;
  j["to_state"] = a.to_state;
  return j;
}

}  // namespace

int run_grasps(const GraspsArgs& a) {
  const auto obj = formats::load_object(a.object);
  const Eigen::Isometry3d initial = formats::pose_from_xyz_quaternion(a.initial, "--initial", "");
  const runtime::GraspGraph graph(obj);
  const auto r = runtime::reachable_grasps(graph, initial, a.opening);
  if (r.initial_state < 0) throw Error(a.object, "dmg", "the object has no grasps for this gripper");
  const auto& g0 = graph.state(r.initial_state);
  if (a.json) {
    nlohmann::ordered_json j;
    j["object"] = a.object;
    j["initial_state"] = {{"state", r.initial_state},
                          {"node", g0.node},
                          {"angle_deg", g0.angle * obj.dmg.angle_step_deg},
                          {"pose", pose(graph.tcp_pose(r.initial_state))},
                          {"snap_distance", r.snap_distance}};
    j["grasps"] = nlohmann::ordered_json::array();
    for (const auto& gr : r.grasps) {
      nlohmann::ordered_json e;
      const auto& s = graph.state(gr.state);
      e["state"] = gr.state;
      e["node"] = s.node;
      e["opposite_patch"] = obj.dmg.nodes[s.node].opposite_patch;
      e["angle_deg"] = s.angle * obj.dmg.angle_step_deg;
      e["pose"] = pose(gr.pose);
      e["opening"] = gr.opening;
      e["cost"] = gr.cost;
      e["contacts"] = {vec(graph.contact1(gr.state)), vec(graph.contact2(gr.state))};
      e["actions"] = nlohmann::ordered_json::array();
      for (const auto& act : r.actions_to(graph, gr.state)) e["actions"].push_back(action_json(act));
      j["grasps"].push_back(e);
    }
    std::cout << j.dump(1) << "\n";
    return 0;
  }
  std::printf("initial grasp: state %d (node %d, angle %g deg), %g from the given pose\n", r.initial_state, g0.node,
              g0.angle * obj.dmg.angle_step_deg, r.snap_distance);
  std::printf("%zu reachable grasps (of %d)\n", r.grasps.size(), graph.size());
  std::printf("%8s %6s %8s %9s %9s %7s  %s\n", "state", "node", "angle", "opening", "cost", "actions",
              "pose x y z qx qy qz qw");
  for (const auto& gr : r.grasps) {
    const auto& s = graph.state(gr.state);
    const auto p = pose(gr.pose);
    std::printf("%8d %6d %8g %9.4f %9.4f %7zu ", gr.state, s.node, s.angle * obj.dmg.angle_step_deg, gr.opening,
                gr.cost, r.actions_to(graph, gr.state).size());
    for (const auto& v : p) std::printf(" %.4f", v.get<double>());
    std::printf("\n");
  }
  return 0;
}

}  // namespace dmgplace::cli
