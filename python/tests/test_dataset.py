"""`dmgplace batch-collect`'s dataset as an analyst meets it (issue 61): every table is one
pandas.DataFrame in one call, and a run's arm path and in-hand actions read back equal to its
result.json. A tiny batch (dmgarm, the eraser, a table corner; two seeds stopped after 40 rounds) is
run once per session with the dmgplace CLI ($DMGPLACE_CLI, default build/release/tools/dmgplace).
pandas and h5py are required (scripts/deps installs them): a missing one fails, never skips."""
import json
import os
import pathlib
import subprocess

import h5py
import numpy as np
import pandas as pd
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CLI = os.environ.get("DMGPLACE_CLI", str(ROOT / "build" / "release" / "tools" / "dmgplace"))
DATA = ROOT / "datasets"
TABLES = ["runs", "path", "retreat", "actions", "fingers", "trace", "joints", "offsets"]


def cli(*args):
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, f"dmgplace {' '.join(map(str, args))}: {done.stderr}"
    return done


def schema(batch):
    with h5py.File(batch / "dataset.h5", "r") as f:
        return f.attrs["schema"].decode(), int(f.attrs["schema_version"])


def manifest():
    robot = DATA / "robots" / "dmgarm"
    return f"""name: analyst
robots:
  arm: {{urdf: {robot / "dmgarm.urdf"}, srdf: {robot / "dmgarm.srdf"}, arm: "dmgarm_link0:dmgarm_tcp"}}
objects:
  eraser: {{mesh: eraser.stl}}
environments:
  table: {{scene: {DATA / "scenes" / "table.yaml"}, volume: [0.3, -0.3, 0.4, 0.8, 0.3, 0.7],
          flags: [--resolution, "0.02", --margin, "0.9", --sdf-resolution, "0.04", --band, "0.25"]}}
queries:
  - name: q
    robot: arm
    objects: [eraser]
    environments: [table]
    initial_grasps: {{top: [0, 0, 0.0175, 1, 0, 0, 0]}}
    start: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]
    variants: [full]
    seeds: 2
    time_limit: 60
    iterations: 40
"""


@pytest.fixture(scope="session")
def batch(tmp_path_factory):
    d = tmp_path_factory.mktemp("batch")
    cli("make-objects", "--out", d)
    (d / "m.yaml").write_text(manifest())
    cli("batch", d / "m.yaml", "--out", d / "out", "--jobs", 2)
    cli("batch-collect", d / "out", "--out", d / "dataset.h5", "--csv", d / "runs.csv")
    return d


@pytest.fixture(scope="session")
def tables(batch):
    # The one-line read, per table (strings come as bytes, as h5py gives them).
    with h5py.File(batch / "dataset.h5", "r") as f:
        return {t: pd.DataFrame({k: c[()] for k, c in f[t].items()}) for t in TABLES}


def result_of(batch, task_id):
    (folder,) = (batch / "out" / "runs").glob(f"*-{task_id[:12]}")
    return json.loads((folder / "result.json").read_text())


def test_every_table_is_one_dataframe_with_a_row_per_item(batch, tables):
    runs = tables["runs"]
    assert len(runs) == 2
    assert list(runs.columns[:6]) == ["task_id", "robot", "object", "environment", "grasp", "variant"]
    assert set(runs.robot) == {b"arm"} and runs.solved.all()
    assert (runs.path_waypoints.sum(), runs.in_hand_actions.sum()) == (len(tables["path"]), len(tables["actions"]))
    assert runs.improvements.sum() == len(tables["trace"])
    assert len(tables["offsets"]) == len(runs) + 1
    assert list(tables["joints"].name.str.decode("utf-8")) == [f"dmgarm_joint{k}" for k in range(1, 8)]
    # `.asstr()` gives str instead of bytes, still one call.
    with h5py.File(batch / "dataset.h5", "r") as f:
        named = pd.DataFrame({k: c.asstr()[()] if c.dtype.kind == "S" else c[()] for k, c in f["runs"].items()})
    assert list(named.variant) == ["full", "full"]
    assert schema(batch) == ("dmgplace.dataset", 2)


def test_a_runs_path_and_in_hand_actions_equal_its_result_json(batch, tables):
    runs, path, actions = tables["runs"], tables["path"], tables["actions"]
    assert (runs.in_hand_actions > 0).any(), "no run has in-hand actions: the comparison below proves little"
    for i, task_id in enumerate(runs.task_id.str.decode("utf-8")):
        best = result_of(batch, task_id)["best"]
        q = path[path.run == i].filter(regex=r"^q\d+$").to_numpy()
        np.testing.assert_array_equal(q, np.array(best["path"]))
        mine = actions[actions.run == i]
        assert list(mine.step) == list(range(len(best["in_hand"])))
        assert list(mine.type.str.decode("utf-8")) == [a["type"] for a in best["in_hand"]]
        assert list(mine.from_state) == [a["from_state"] for a in best["in_hand"]]
        assert list(mine.to_state) == [a["to_state"] for a in best["in_hand"]]
        for row, a in zip(mine.itertuples(), best["in_hand"]):
            if a["type"] == "push":
                assert (row.distance, row.push_direction_x, row.push_direction_z) == (
                    a["distance"], a["push_direction"][0], a["push_direction"][2])
                assert np.isnan(row.angle)
            else:
                assert (row.angle, row.axis_y, row.pivot_x) == (a["angle"], a["axis"][1], a["pivot"][0])
                assert np.isnan(row.distance)


def test_offsets_give_the_same_ragged_rows_without_a_group_by(batch, tables):
    with h5py.File(batch / "dataset.h5", "r") as f:
        offsets = f["offsets/path"][()]
        q = np.column_stack([f["path"][f"q{j}"][()] for j in range(7)])
    for i, task_id in enumerate(tables["runs"].task_id.str.decode("utf-8")):
        np.testing.assert_array_equal(q[offsets[i]:offsets[i + 1]], result_of(batch, task_id)["best"]["path"])


def test_the_objective_trace_and_counters_equal_result_json(batch, tables):
    trace = tables["trace"]
    for i, task_id in enumerate(tables["runs"].task_id.str.decode("utf-8")):
        result = result_of(batch, task_id)
        mine = trace[trace.run == i]
        assert list(mine.objective) == [s["objective"] for s in result["improvements"]]
        assert list(mine.iterations) == [s["counters"]["iterations"] for s in result["improvements"]]
        for name, value in result["counters"].items():
            assert tables["runs"][name][i] == value, name


def test_the_csv_is_the_runs_table(batch, tables):
    csv = pd.read_csv(batch / "runs.csv", dtype={"task_id": str}, float_precision="round_trip")  # exact doubles
    runs = tables["runs"]
    assert list(csv.columns) == list(runs.columns)
    assert list(csv.task_id) == list(runs.task_id.str.decode("utf-8"))
    np.testing.assert_array_equal(csv.objective.to_numpy(), runs.objective.to_numpy())
    np.testing.assert_array_equal(csv.pose_qw.to_numpy(), runs.pose_qw.to_numpy())


def test_validate_accepts_the_dataset(batch):
    assert cli("validate", batch / "dataset.h5").stdout.strip().endswith("ok")
