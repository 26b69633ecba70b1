"""igms.sweep on a local Ray, started and stopped here (the test runs in a private network namespace):
the same rows as a serial loop, Coulomb's stop distances, a failing run recorded, a rerun that skips
what is done, the same rows for the same seed, and no Ray process left behind."""
import os
import subprocess
import sys
import time

import numpy as np
import pytest
import yaml

import igms
from igms import sweeps
from igms.sweep_spec import SpecError, expand, load_spec, set_key

G, H = 9.81, 0.001
GRID = {"scene": "scenes/box_slide.yaml", "seconds": 1.5,
        "grid": {"materials.wood.friction": [0.2, 0.5, 0.8], "bodies[box].v": [[0.5, 0, 0], [1, 0, 0], [2, 0, 0]]},
        "metrics": ["final_pose", "displacement", "max_penetration", "max_contacts", "contact_solve.unconverged"]}


def ray_processes():
    """Ray's processes on this machine: {pid: command line}."""
    out = subprocess.run(["ps", "-eo", "pid=,args="], capture_output=True, text=True).stdout
    return {line.split()[0]: line.strip() for line in out.splitlines()
            if any(k in line for k in ("raylet", "gcs_server", "ray::", "ray/_private", "dashboard/agent"))}


def assert_none_left(before):
    """Every Ray process started since `before` ends within 30 s of the sweep's return."""
    deadline = time.time() + 30
    while set(ray_processes()) - set(before) and time.time() < deadline:
        time.sleep(0.5)
    left = {pid: args for pid, args in ray_processes().items() if pid not in before}
    assert not left, f"Ray processes left behind: {left}"


def discrete_stop(v0, mu):
    """The step's own stop (contact_analytic_test): x = h sum (v0 - k mu g h) while positive."""
    a = mu * G
    return sum(H * (v0 - k * a * H) for k in range(1, 100000) if v0 - k * a * H > 0)


def metrics(frame):
    return frame.drop(columns=["duration_s", "worker"]).to_dict("records")


def same(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.keys() == y.keys()
        for k in x:
            np.testing.assert_array_equal(np.asarray(x[k], dtype=object), np.asarray(y[k], dtype=object), err_msg=k)


def test_a_sweep_on_ray_matches_a_serial_loop_and_coulomb(tmp_path):
    before = ray_processes()
    on_ray = igms.sweep(GRID, tmp_path / "ray", workers=2, progress=False)
    serial = sweeps.run_sweep(GRID, str(tmp_path / "serial"), serial=True, progress=False)
    same(metrics(on_ray), metrics(serial))  # bit for bit
    assert list(on_ray["run"]) == list(range(9)) and on_ray["error"].isna().all()
    for _, row in on_ray.iterrows():
        mu, v0 = row["materials.wood.friction"], row["bodies[box].v"][0]
        assert row["displacement.box"][0] == pytest.approx(discrete_stop(v0, mu), abs=1e-9)
        assert row["final_pose.box"][0] == pytest.approx(discrete_stop(v0, mu), abs=1e-9)
        assert abs(discrete_stop(v0, mu) - v0**2 / (2 * mu * G)) < H * v0  # the analytic stop, within h v0
        assert row["max_contacts"] == 4 and row["contact_solve.unconverged"] == 0
    # Ray was started here and is gone: no raylet, GCS or worker outlives the sweep.
    assert_none_left(before)


def test_a_failing_run_is_recorded_and_the_sweep_goes_on(tmp_path):
    spec = dict(GRID, grid={"materials.wood.friction": [0.5, -1.0, 0.2]}, seconds=0.5)
    rows = sweeps.run_sweep(spec, str(tmp_path), serial=True, progress=False)
    assert rows["error"].isna().tolist() == [True, False, True]
    assert "SceneError" in rows["error"][1] and "materials.wood.friction: must be >= 0" in rows["error"][1]
    assert rows["max_contacts"][0] == 4 and np.isnan(rows["max_contacts"][1])


def test_a_rerun_skips_what_is_done(tmp_path, monkeypatch):
    spec = dict(GRID, seconds=0.2)
    first = sweeps.run_sweep(spec, str(tmp_path), serial=True, progress=False)
    real = sweeps.run_one

    def must_not_run(spec, run):
        raise AssertionError(f"run {run['run']} ran again")

    monkeypatch.setattr(sweeps, "run_one", must_not_run)
    again = sweeps.run_sweep(spec, str(tmp_path), serial=True, progress=False)
    same(first.to_dict("records"), again.to_dict("records"))
    # A wider grid runs only its new runs.
    wider = dict(spec, grid=dict(spec["grid"], **{"materials.wood.friction": [0.2, 0.5, 0.8, 1.0]}))
    ran = []
    monkeypatch.setattr(sweeps, "run_one", lambda s, r: ran.append(r["run"]) or real(s, r))
    rows = sweeps.run_sweep(wider, str(tmp_path), serial=True, progress=False)
    assert ran == [9, 10, 11] and len(rows) == 12


def test_the_same_seed_gives_the_same_rows_on_ray(tmp_path):
    import ray
    spec = {"scene": "scenes/box_slide.yaml", "seconds": 0.3, "metrics": ["final_pose"],
            "random": {"n": 24, "seed": 7, "ranges": {"materials.wood.friction": [0.1, 1.0],
                                                      "bodies[box].v": [[0, 0, 0], [2, 1, 0]]}}}
    before = ray_processes()
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, logging_level="ERROR")
    try:
        a = sweeps.run_sweep(spec, str(tmp_path / "a"), progress=False)
        b = sweeps.run_sweep(spec, str(tmp_path / "b"), progress=False)
        c = sweeps.run_sweep(dict(spec, random=dict(spec["random"], seed=8)), str(tmp_path / "c"), progress=False)
    finally:
        ray.shutdown()
    same(metrics(a), metrics(b))
    assert not np.allclose(a["materials.wood.friction"], c["materials.wood.friction"])
    assert a["materials.wood.friction"].between(0.1, 1.0).all()
    v = np.stack(a["bodies[box].v"])
    assert v.shape == (24, 3) and np.all(v >= 0) and np.all(v <= [2, 1, 0])
    assert_none_left(before)


def test_keys_and_specs_are_checked():
    doc = yaml.safe_load(open("scenes/box_slide.yaml"))
    set_key(doc, "bodies[box].mass", 2.0)
    set_key(doc, "bodies[0].xyz", [0, 0, 0.2])
    set_key(doc, "materials.wood.restitution", 0.1)
    assert doc["bodies"][0]["mass"] == 2.0 and doc["bodies"][0]["xyz"] == [0, 0, 0.2]
    assert doc["materials"]["wood"]["restitution"] == 0.1
    with pytest.raises(SpecError, match="no entry named 'ball'.*box"):
        set_key(doc, "bodies[ball].mass", 1)
    with pytest.raises(SpecError, match="'materails' is not in the document"):
        set_key(doc, "materails.wood.friction", 1)
    with pytest.raises(SpecError, match="index 3 out of range"):
        set_key(doc, "bodies[3].mass", 1)
    with pytest.raises(SpecError, match="expected a path"):
        set_key(doc, "bodies..mass", 1)
    with pytest.raises(SpecError, match="unknown metric 'speed'"):
        load_spec(dict(GRID, metrics=["speed"]))
    with pytest.raises(SpecError, match="give 'grid' or 'random'"):
        load_spec({"scene": "scenes/box_slide.yaml"})
    with pytest.raises(SpecError, match="unknown keys"):
        load_spec(dict(GRID, grdi={}))
    runs = expand(load_spec(GRID))
    assert len(runs) == 9 and len({r["run_id"] for r in runs}) == 9
    assert runs[1]["params"] == {"materials.wood.friction": 0.2, "bodies[box].v": [1, 0, 0]}


def test_a_script_key_changes_the_hand(tmp_path):
    spec = {"scene": "scenes/box_push.yaml", "script": "scenes/box_push_hand.yaml", "seconds": 2.0,
            "grid": {"script.waypoints[2].xyz": [[-0.13, 0, 0.1], [0.07, 0, 0.1]]},
            "metrics": ["displacement", "max_robot_force"]}
    rows = sweeps.run_sweep(spec, str(tmp_path), serial=True, progress=False)
    assert rows["error"].isna().all()
    still, pushed = rows["displacement.box"]
    assert abs(still[0]) < 1e-9 and pushed[0] > 0.01  # the hand that stays put moves nothing


def test_the_command_line(tmp_path):
    spec = tmp_path / "spec.yaml"
    spec.write_text(yaml.safe_dump(dict(GRID, seconds=0.1)))
    env = dict(os.environ)
    cli = [sys.executable, "-m", "igms.sweep_cli"]
    r = subprocess.run(cli + [str(spec), "--out", str(tmp_path / "out"), "--serial", "--no-progress"],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert "9 runs in" in r.stdout and "0 failed" in r.stdout
    bad = tmp_path / "bad.yaml"
    bad.write_text("scene: scenes/box_slide.yaml\ngrid: {materials.wood.friction: [0.1]}\nmetrics: [speed]\n")
    r = subprocess.run(cli + [str(bad), "--out", str(tmp_path / "out2")], capture_output=True, text=True, env=env)
    assert r.returncode == 2 and "unknown metric 'speed'" in r.stderr
    bad.write_text("scene: scenes/box_slide.yaml\ngrid: {bodies[box].v: [[1, 0, 0]]}\n")  # [ in a flow key
    r = subprocess.run(cli + [str(bad), "--out", str(tmp_path / "out2")], capture_output=True, text=True, env=env)
    assert r.returncode == 2 and "bad.yaml: not YAML" in r.stderr and "Traceback" not in r.stderr
