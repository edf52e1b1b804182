"""The dmgplace Python module (issue 18): the same answers as the CLI, callbacks, errors, stopping
and threads. Artifacts are baked once per session with the dmgplace CLI ($DMGPLACE_CLI, default
build/release/tools/dmgplace)."""
import _thread
import json
import os
import pathlib
import subprocess
import signal
import threading

import numpy as np
import pytest

import dmgplace

ROOT = pathlib.Path(__file__).resolve().parents[2]
CLI = os.environ.get("DMGPLACE_CLI", str(ROOT / "build" / "release" / "tools" / "dmgplace"))
DATA = ROOT / "datasets"
QUERY = """robot: arm.h5
object: eraser.h5
environment: table.h5
start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]
initial_grasp: {pose: [0, 0, 0.0175, 1, 0, 0, 0]}
time_limit: 30
seed: 2
"""


def cli(*args):
    return subprocess.run([CLI, *map(str, args)], check=True, capture_output=True, text=True)


@pytest.fixture(scope="session")
def artifacts(tmp_path_factory):
    d = tmp_path_factory.mktemp("artifacts")
    cli("make-objects", "--out", d)
    cli("bake-object", d / "eraser.stl", "--out", d / "eraser.h5")
    cli("bake-robot", DATA / "robots/dmgarm/dmgarm.urdf", "--srdf", DATA / "robots/dmgarm/dmgarm.srdf",
        "--arm", "dmgarm_link0:dmgarm_tcp", "--out", d / "arm.h5")
    cli("bake-env", DATA / "scenes/table.yaml", "--volume", "0.3,-0.3,0.4,0.8,0.3,0.7", "--resolution", "0.02",
        "--margin", "0.9", "--sdf-resolution", "0.04", "--band", "0.25", "--out", d / "table.h5")
    (d / "q.yaml").write_text(QUERY)
    return d


@pytest.fixture(scope="session")
def world(artifacts):
    return dmgplace.World.load(artifacts / "arm.h5", artifacts / "eraser.h5", artifacts / "table.h5")


def test_placement_equals_the_cli_for_the_same_query_and_seed(artifacts, world):
    out = artifacts / "cli_out"
    cli("place", artifacts / "q.yaml", "--iterations", 60, "--seed", 5, "--out", out)
    expected = json.loads((out / "result.json").read_text())
    got = dmgplace.place(world, dmgplace.read_query(artifacts / "q.yaml"), iterations=60, seed=5)
    assert got["solved"] == expected["solved"]
    assert got["solved"], got["reason"]
    assert got["best"]["objective"] == pytest.approx(expected["best"]["objective"], abs=1e-12)
    assert got["best"]["grasp_state"] == expected["best"]["grasp"]["state"]
    assert len(got["improvements"]) == len(expected["improvements"])
    # The timed trajectory is the CLI's (trajectory.json), as numpy arrays.
    timed = json.loads((out / "trajectory.json").read_text())["approach"]
    np.testing.assert_allclose(got["best"]["trajectory"]["positions"], np.array(timed["positions"]), atol=1e-12)
    assert got["best"]["trajectory"]["duration"] == pytest.approx(expected["best"]["duration"], abs=1e-12)
    # In-hand actions, when there are any, come with the statement that no pusher was planned.
    assert ("in_hand_execution" in got) == bool(got["best"]["in_hand"]) == ("in_hand_execution" in expected)


def test_the_callback_fires_for_every_improvement_in_order(artifacts, world):
    seen = []
    r = dmgplace.place(world, dmgplace.read_query(artifacts / "q.yaml"), iterations=60, seed=5,
                       on_solution=lambda s: seen.append(s["objective"]))
    assert seen == [s["objective"] for s in r["improvements"]]
    assert seen == sorted(seen) and len(set(seen)) == len(seen)
    best = r["best"]
    assert best["pose"].shape == (4, 4) and best["path"].shape[1] == world.dof
    np.testing.assert_allclose(best["path"][0], [0, -0.785, 0, -2.356, 0, 1.571, 0.785])


def test_a_bad_artifact_raises_an_error_naming_the_file(artifacts, tmp_path):
    bad = tmp_path / "broken.h5"
    bad.write_bytes(b"not an artifact")
    with pytest.raises(dmgplace.Error, match=str(bad)):
        dmgplace.World.load(artifacts / "arm.h5", bad, artifacts / "table.h5")
    assert dmgplace.validate(bad) and str(bad) in dmgplace.validate(bad)[0]
    with pytest.raises(dmgplace.Error, match="outside its range"):
        q = tmp_path / "q.yaml"
        q.write_text(QUERY + "options: {threads: 100000}\n")
        dmgplace.read_query(q, artifacts)


def test_joints_outside_the_arm_are_set_by_name_or_refused(artifacts):
    with pytest.raises(dmgplace.Error, match="no joint of that name"):
        dmgplace.World.load(artifacts / "arm.h5", artifacts / "eraser.h5", artifacts / "table.h5",
                            joint_values={"elbow_of_another_arm": 1.0})
    with pytest.raises(dmgplace.Error, match="planning chain"):
        dmgplace.World.load(artifacts / "arm.h5", artifacts / "eraser.h5", artifacts / "table.h5",
                            joint_values={"dmgarm_joint1": 0.0})


def test_a_stop_callable_ends_place_promptly(artifacts, world):
    # Without the stop the search would run its 60 s and poll many more times.
    calls = []
    r = dmgplace.place(world, dmgplace.read_query(artifacts / "q.yaml"), time_limit=60,
                       stop=lambda: calls.append(1) or len(calls) > 5)
    assert len(calls) == 6
    assert "solved" in r


def test_keyboard_interrupt_ends_place(artifacts, world):
    # Uninterrupted, place would return normally after its 60 s instead of raising. Ctrl-C is
    # pressed every 0.2 s while place runs (once is enough; CI once saw a single press at 0.5 s
    # go unanswered); the handler raises only inside place, so a press after it returns is harmless.
    in_place, done = threading.Event(), threading.Event()

    def handler(signum, frame):
        if in_place.is_set():
            raise KeyboardInterrupt

    def press():
        while not done.wait(0.2):
            _thread.interrupt_main()

    previous = signal.signal(signal.SIGINT, handler)
    presser = threading.Thread(target=press, daemon=True)
    presser.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            in_place.set()
            try:
                dmgplace.place(world, dmgplace.read_query(artifacts / "q.yaml"), time_limit=60)
            finally:
                in_place.clear()
    finally:
        done.set()
        presser.join()
        signal.signal(signal.SIGINT, previous)


def test_two_threads_on_one_world_get_what_each_gets_alone(artifacts, world):
    query = dmgplace.read_query(artifacts / "q.yaml")
    alone = [dmgplace.place(world, query, iterations=40, seed=s) for s in (11, 12)]
    together = [None, None]

    def run(i, s):
        together[i] = dmgplace.place(world, query, iterations=40, seed=s)

    threads = [threading.Thread(target=run, args=(i, s)) for i, s in enumerate((11, 12))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(alone, together):
        assert a["solved"] == b["solved"]
        assert [s["objective"] for s in a["improvements"]] == [s["objective"] for s in b["improvements"]]


def test_reachable_grasps_and_arm_motion(world):
    g = dmgplace.reachable_grasps(world, [0, 0, 0.0175, 1, 0, 0, 0])
    assert g["initial_state"] >= 0 and g["grasps"][0]["state"] == g["initial_state"]
    costs = [x["cost"] for x in g["grasps"]]
    assert costs == sorted(costs)
    # An opening is a width or unset (None), never a -1 meaning "unset".
    with pytest.raises(dmgplace.Error, match="opening"):
        dmgplace.reachable_grasps(world, [0, 0, 0.0175, 1, 0, 0, 0], opening=-1)
    start = np.array([0, -0.785, 0, -2.356, 0, 1.571, 0.785])
    goal = start + np.array([0.3, 0.1, 0, 0.1, 0, 0, 0])
    m = dmgplace.plan_motion(world, start, goal, time_limit=5)
    assert m["solved"], m["reason"]
    np.testing.assert_allclose(m["path"][0], start)
    np.testing.assert_allclose(m["path"][-1], goal)
    assert world.tcp_pose(start).shape == (4, 4)


def test_arm_motion_is_timed_within_the_limits(world):
    start = np.array([0, -0.785, 0, -2.356, 0, 1.571, 0.785])
    goal = start + np.array([0.3, 0.1, 0, 0.1, 0, 0, 0])
    full = dmgplace.plan_motion(world, start, goal, time_limit=5)
    half = dmgplace.plan_motion(world, start, goal, time_limit=5, velocity_scaling=0.5, acceleration_scaling=0.25)
    for m in (full, half):
        t = m["trajectory"]
        assert t["time"].ndim == 1 and t["positions"].shape == (len(t["time"]), world.dof)
        assert np.all(np.diff(t["time"]) > 0)
        np.testing.assert_allclose(t["positions"][0], start, atol=1e-9)
        np.testing.assert_allclose(t["positions"][-1], goal, atol=1e-9)
        np.testing.assert_allclose(t["velocities"][[0, -1]], 0, atol=1e-9)
    # Slower limits take longer (the same seed plans the same path).
    np.testing.assert_allclose(full["path"], half["path"])
    assert half["trajectory"]["duration"] > 1.5 * full["trajectory"]["duration"]
    with pytest.raises(dmgplace.Error, match="velocity_scaling"):
        dmgplace.plan_motion(world, start, goal, velocity_scaling=0)


def test_inspect_gives_the_header_as_a_dict(artifacts):
    info = dmgplace.inspect(artifacts / "eraser.h5")
    assert info["schema"].startswith("dmgplace.object") and int(info["triangles"]) == 12
