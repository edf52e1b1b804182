// The `dmgplace` Python module: load artifacts once, then placement, in-hand grasp and arm motion
// queries from Python, over the same embedding API as C++ (dmgplace/runtime.hpp). Poses are 4x4
// numpy arrays (or [x, y, z, qx, qy, qz, qw]); joint paths are (N, dof) arrays; errors are
// dmgplace.Error (a RuntimeError) carrying the file, element and reason. place() releases the GIL
// while it plans and takes it back only to call `on_solution` / `stop`, so other Python threads
// run meanwhile; Ctrl-C ends it within one search round and raises KeyboardInterrupt.
#include <pybind11/eigen.h>
#include "dmgplace/formats/pose_input.hpp"
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/runtime.hpp"
#include "dmgplace/tools/placement/placement_query_file.hpp"

namespace py = pybind11;
using namespace dmgplace;

namespace {

Eigen::Isometry3d pose_from(const py::object& o, const char* what) {
  const auto a = py::cast<Eigen::MatrixXd>(py::module_::import("numpy").attr("asarray")(o, "float64"));
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  if (a.rows() == 4 && a.cols() == 4) {
    p.matrix() = a;
  } else if (a.size() == 7) {
    const double v[7] = {a(0), a(1), a(2), a(3), a(4), a(5), a(6)};
    p = formats::pose_from_xyz_quaternion(v, "python", what);
  } else {
    throw Error("python", what, "expected a 4x4 matrix or [x, y, z, qx, qy, qz, qw]");
  }
  if (!p.matrix().allFinite()) throw Error("python", what, "not finite");
  return p;
}

Eigen::MatrixXd path_array(const runtime::JointPath& path) {
  Eigen::MatrixXd m(Eigen::Index(path.size()), path.empty() ? 0 : Eigen::Index(path[0].size()));
  for (std::size_t i = 0; i < path.size(); ++i)
    for (std::size_t j = 0; j < path[i].size(); ++j) m(Eigen::Index(i), Eigen::Index(j)) = path[i][j];
  return m;
}

// A timed trajectory as numpy arrays: time (N,), positions, velocities, accelerations (N, dof).
py::dict trajectory_dict(const runtime::Trajectory& t) {
  py::dict d;
  d["time"] = Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(t.time.data(), Eigen::Index(t.time.size())));
  d["positions"] = path_array(t.positions);
  d["velocities"] = path_array(t.velocities);
  d["accelerations"] = path_array(t.accelerations);
  d["duration"] = t.duration();
  return d;
}

py::dict action_dict(const runtime::InHandAction& a) {
  py::dict d;
  d["type"] = a.type == runtime::GraspMove::Translation ? "push" : "rotate";
  d["from_state"] = a.from_state;
  d["to_state"] = a.to_state;
  d["distance"] = a.distance;
  d["push_direction"] = Eigen::Vector3d(a.push_direction);
  d["angle"] = a.angle;
  d["axis"] = Eigen::Vector3d(a.axis);
  d["pivot"] = Eigen::Vector3d(a.pivot);
  return d;
}

py::dict solution_dict(const runtime::PlacementSolution& s) {
  py::dict d;
  d["time"] = s.time;
  d["objective"] = s.objective;
  d["pose"] = Eigen::Matrix4d(s.pose.matrix());
  d["face"] = s.face;
  d["region"] = s.region;
  d["grasp_state"] = s.grasp_state;
  d["grasp"] = Eigen::Matrix4d(s.grasp.matrix());
  d["opening"] = s.opening;
  d["grasp_cost"] = s.grasp_cost;
  py::list actions;
  for (const auto& a : s.in_hand) actions.append(action_dict(a));
  d["in_hand"] = actions;
  d["path"] = path_array(s.path);
  d["retreat"] = path_array(s.retreat);
  d["release_opening"] = s.release_opening;
  d["trajectory"] = trajectory_dict(s.trajectory);
  d["retreat_trajectory"] = trajectory_dict(s.retreat_trajectory);
  py::list pushes;
  for (const auto& p : s.pushes) {
    py::dict x;
    x["action"] = p.action;
    x["contact"] = Eigen::Vector3d(p.contact);
    x["direction"] = Eigen::Vector3d(p.direction);
    x["object_before"] = Eigen::Matrix4d(p.object_before.matrix());
    x["object_after"] = Eigen::Matrix4d(p.object_after.matrix());
    x["grasp_after"] = Eigen::Matrix4d(p.grasp_after.matrix());
    x["path"] = path_array(p.path);
    x["push_begin"] = p.push_begin;
    x["push_end"] = p.push_end;
    x["trajectory"] = trajectory_dict(p.trajectory);
    pushes.append(x);
  }
  d["pushes"] = pushes;  // one per in-hand action when the query names a pusher arm
  return d;
}

py::dict result_dict(const runtime::PlacementResult& r) {
  py::dict d;
  d["solved"] = r.solved();
  d["reason"] = r.reason;
  d["seconds"] = r.seconds;
  d["reachable_grasps"] = r.reachable_grasps;
  d["initial_state"] = r.initial_state;
  d["snap_distance"] = r.snap_distance;
  d["initial_opening"] = r.initial_opening;
  py::list imp;
  for (const auto& s : r.improvements) imp.append(solution_dict(s));
  d["improvements"] = imp;
  d["best"] = r.solved() ? py::object(solution_dict(r.best())) : py::none();
  // Who performs the in-hand actions: the query's pusher arm, or (none named) a second arm or a
  // fixture that dmgplace does not plan for. Said wherever there are some.
  if (r.solved() && !r.best().in_hand.empty())
    d["in_hand_execution"] = r.best().pushes.empty() ? runtime::kInHandExecutionNote : runtime::kInHandPlannedNote;
  d["pusher_joints"] = r.pusher_joints;
  d["samples"] = r.counters.samples;
  d["goals"] = r.counters.goals;
  return d;
}

// One query as read from a QUERY.yaml (the CLI's reader), resolved against the world.
struct Query {
  tools::PlacementQueryFile file;
};

py::dict place_query(const World& world, Query q, std::optional<double> time_limit, std::optional<std::uint64_t> seed,
                     std::optional<long> iterations, const py::object& on_solution, const py::object& stop) {
  if (seed) q.file.query.seed = *seed;
  q.file.query.q0 = tools::resolve_start(q.file, world.kinematics());
  const double limit = time_limit ? *time_limit : q.file.time_limit;
  if (!(limit >= 0 && limit <= 1e6)) throw Error("place", "time_limit", "must be in [0, 1e6] s");
  const auto timer = stop_after_seconds(limit);
  const auto rounds = iterations ? stop_after_iterations(*iterations) : StopCondition();
  bool interrupted = false;
  std::optional<py::error_already_set> callback_error;
  const auto stop_now = [&] {
    if ((rounds && rounds()) || timer()) return true;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {  // Ctrl-C: leave the exception set, end the search
      interrupted = true;
      return true;
    }
    if (!stop.is_none()) {
      try {
        return stop().cast<bool>();
      } catch (py::error_already_set& e) {
        callback_error = std::move(e);
        return true;
      }
    }
    return false;
  };
  const auto callback = [&](const runtime::PlacementSolution& s) {
    if (on_solution.is_none() || callback_error) return;
    py::gil_scoped_acquire gil;
    try {
      on_solution(solution_dict(s));
    } catch (py::error_already_set& e) {
      callback_error = std::move(e);
    }
  };
  runtime::PlacementResult r;
  {
    py::gil_scoped_release release;
    r = dmgplace::place(world, q.file.query, stop_now, callback);
  }
  if (interrupted) throw py::error_already_set();
  if (callback_error) throw std::move(*callback_error);
  return result_dict(r);
}

}  // namespace

PYBIND11_MODULE(dmgplace, m) {
  m.doc() = "Placing objects with prior in-hand manipulation (Dexterous Manipulation Graphs): the embedding runtime";
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      error(e.what());
    }
  });

  py::class_<World, std::shared_ptr<World>>(m, "World",
                                            "The three artifacts, loaded once; immutable, shareable between threads")
      .def_static(
          "load",
          [](const std::filesystem::path& robot, const std::filesystem::path& object, const std::filesystem::path& env,
             std::optional<double> finger_opening, const std::map<std::string, double>& joint_values) {
            return std::const_pointer_cast<World>(World::load(robot, object, env, finger_opening, joint_values));
          },
          py::arg("robot"), py::arg("object"), py::arg("environment"), py::arg("finger_opening") = py::none(),
          py::arg("joint_values") = std::map<std::string, double>{}, py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("dof", &World::dof)
      .def_property_readonly("joint_names", &World::joint_names)
      .def_property_readonly("lower_limits", &World::lower_limits)
      .def_property_readonly("upper_limits", &World::upper_limits)
      .def(
          "tcp_pose", [](const World& w, const Eigen::VectorXd& q) { return Eigen::Matrix4d(w.tcp_pose(q).matrix()); },
          py::arg("q"));

  py::class_<Query>(m, "Query", "A placement query read from a QUERY.yaml (as `dmgplace place` reads it)")
      .def_property_readonly("robot", [](const Query& q) { return q.file.robot; })
      .def_property_readonly("object", [](const Query& q) { return q.file.object; })
      .def_property_readonly("environment", [](const Query& q) { return q.file.environment; })
      .def_property_readonly("time_limit", [](const Query& q) { return q.file.time_limit; })
      .def_property(
          "seed", [](const Query& q) { return q.file.query.seed; },
          [](Query& q, std::uint64_t s) { q.file.query.seed = s; })
      .def_property(
          "variant", [](const Query& q) { return std::string(runtime::to_string(q.file.query.variant)); },
          [](Query& q, const std::string& v) {
            const auto parsed = runtime::parse_variant(v);
            if (!parsed) throw Error("python", "variant", "unknown variant '" + v + "'");
            q.file.query.variant = *parsed;
          })
      .def_property(
          "initial_grasp", [](const Query& q) { return Eigen::Matrix4d(q.file.query.g0.matrix()); },
          [](Query& q, const py::object& pose) { q.file.query.g0 = pose_from(pose, "initial_grasp"); });

  m.def(
      "read_query",
      [](const std::filesystem::path& path, const std::filesystem::path& artifacts, bool allow_outside) {
        return Query{tools::read_placement_query(path, artifacts, allow_outside)};
      },
      py::arg("path"), py::arg("artifacts") = std::filesystem::path(), py::arg("allow_outside") = false,
      "Reads a QUERY.yaml; relative artifact paths resolve against `artifacts` (default: the query's folder)");

  m.def("place", &place_query, py::arg("world"), py::arg("query"), py::arg("time_limit") = py::none(),
        py::arg("seed") = py::none(), py::arg("iterations") = py::none(), py::arg("on_solution") = py::none(),
        py::arg("stop") = py::none(),
        "Anytime placement search; returns a dict (solved, best, improvements, reason, ...). `on_solution(dict)` is "
        "called for every improvement; `stop()` returning True, `iterations` rounds or `time_limit` seconds end it.");

  m.def(
      "reachable_grasps",
      [](const World& w, const py::object& g0, std::optional<double> opening) {
        const auto r = reachable_grasps(w, pose_from(g0, "g0"), opening);
        py::list grasps;
        for (const auto& g : r.grasps) {
          py::dict d;
          d["state"] = g.state;
          d["pose"] = Eigen::Matrix4d(g.pose.matrix());
          d["opening"] = g.opening;
          d["cost"] = g.cost;
          grasps.append(d);
        }
        py::dict out;
        out["initial_state"] = r.initial_state;
        out["snap_distance"] = r.snap_distance;
        out["grasps"] = grasps;
        return out;
      },
      py::arg("world"), py::arg("g0"), py::arg("opening") = py::none(),
      "G(g0): grasps reachable in-hand, cheapest first");

  m.def(
      "plan_motion",
      [](const World& w, const Eigen::VectorXd& start, const Eigen::VectorXd& goal, const py::object& grasp,
         double time_limit, std::uint64_t seed, double resolution, double velocity_scaling,
         double acceleration_scaling) {
        MotionQuery q;
        q.start = start;
        q.goal = goal;
        if (!grasp.is_none()) q.grasp = pose_from(grasp, "grasp");
        q.time_limit = time_limit;
        q.seed = seed;
        q.resolution = resolution;
        q.timing.velocity_scaling = velocity_scaling;
        q.timing.acceleration_scaling = acceleration_scaling;
        MotionResult r;
        {
          py::gil_scoped_release release;
          r = plan_motion(w, q);
        }
        py::dict d;
        d["solved"] = r.solved;
        d["path"] = path_array(r.path);
        d["trajectory"] = trajectory_dict(r.trajectory);
        d["seconds"] = r.seconds;
        d["reason"] = r.reason;
        return d;
      },
      py::arg("world"), py::arg("start"), py::arg("goal"), py::arg("grasp") = py::none(), py::arg("time_limit") = 1.0,
      py::arg("seed") = 1, py::arg("resolution") = 0.05, py::arg("velocity_scaling") = 1.0,
      py::arg("acceleration_scaling") = 1.0,
      "An arm motion, empty-handed or holding the object at `grasp`, and its timed trajectory");

  m.def(
      "inspect",
      [](const std::filesystem::path& path) {
        py::dict d;
        for (const auto& [k, v] : formats::inspect_artifact(path)) {
          if (d.contains(k)) {
            if (!py::isinstance<py::list>(d[k.c_str()])) {
              py::list l;
              l.append(d[k.c_str()]);
              d[k.c_str()] = l;
            }
            d[k.c_str()].cast<py::list>().append(v);
          } else {
            d[k.c_str()] = v;
          }
        }
        return d;
      },
      py::arg("path"), "An artifact's header and counts as a dict");
  m.def("validate", &formats::validate_artifact, py::arg("path"),
        "Every problem of an artifact file (empty when sound)");
}
