"""igms.sweep: many runs of one scenario with its parameters changed (sweep_spec.py), each a Ray task that
runs the scenario in process through the module, as igms-scenario does, and returns its metrics. Ray starts
a local cluster unless given an address. Results go to OUT/results.parquet, a row per run (run, run_id,
seed, the parameters, the metrics, duration_s, worker, error), sorted by run whatever the order of completion; a run
that fails records its error and the sweep goes on; a rerun skips the run ids already there. Ray, pyarrow
and tqdm are needed here only: `import igms` does not load them."""
import json
import math
import os
import socket
import sys
import tempfile
import time

import yaml

from .sweep_spec import plain, expand, load_spec, set_key

SCRIPT_PREFIX = "script."
RESULTS = "results.parquet"


def _scenario_inputs(spec, params):
    """The run's scene and script as YAML text, with its parameters set."""
    with open(spec["scene"]) as f:
        scene = yaml.safe_load(f)
    script = None
    if spec["script"]:
        with open(spec["script"]) as f:
            script = yaml.safe_load(f)
    for key, value in params.items():
        if key.startswith(SCRIPT_PREFIX):
            if script is None:
                raise ValueError(f"key '{key}': the spec has no script")
            set_key(script, key[len(SCRIPT_PREFIX):], value)
        else:
            set_key(scene, key, value)
    return yaml.safe_dump(scene, sort_keys=False), None if script is None else yaml.safe_dump(script, sort_keys=False)


def _metrics(spec, result, initial):
    out = {}
    for name in spec["metrics"]:
        if name == "final_pose":
            for body, pose in result["bodies"].items():
                out[f"final_pose.{body}"] = pose.tolist()
        elif name == "displacement":
            for body, pose in result["bodies"].items():
                out[f"displacement.{body}"] = (pose[:3] - initial[body]).tolist()
        elif name == "final_q":
            q = result["samples"]["q"]
            out["final_q"] = q[-1].tolist() if len(q) else []
        elif name.startswith("contact_solve."):
            out[name] = result["contact_solve"][name.split(".", 1)[1]]
        else:
            out[name] = result[name]
    return out


def run_one(spec, run):
    """One run, in this process: its row. Any failure becomes the row's error."""
    import igms
    start = time.perf_counter()
    row = {"run": run["run"], "run_id": run["run_id"], "seed": run["seed"], **run["params"], "error": None}
    try:
        scene_text, script_text = _scenario_inputs(spec, run["params"])
        scene = igms.Scene.from_yaml(scene_text, os.path.dirname(spec["scene"]),
                                     f"{spec['scene']} (run {run['run']})")
        initial = {}
        if "displacement" in spec["metrics"]:  # where each body starts (the scene's own initial state)
            at_start = igms.Simulation(scene)
            initial = {b: at_start.body(b).position.copy() for b in at_start.bodies}
        with tempfile.TemporaryDirectory(prefix="igms-sweep-") as tmp:
            script = None
            if script_text is not None:
                script = os.path.join(tmp, os.path.basename(spec["script"]))
                with open(script, "w") as f:
                    f.write(script_text)
            result = igms.run_scenario(scene, script, spec["seconds"], bool(spec.get("device_limits", False)))
        row.update(_metrics(spec, result, initial))
    except Exception as e:  # noqa: BLE001: a failing run is recorded, the sweep goes on
        row["error"] = f"{type(e).__name__}: {e}"
    row["duration_s"] = time.perf_counter() - start
    row["worker"] = _worker()
    return row


def _worker():
    """Where a run ran: the Ray node's address (or this host's name) and the process."""
    ray = sys.modules.get("ray")  # loaded in a Ray worker; a serial sweep does not load it
    host = ray.util.get_node_ip_address() if ray is not None and ray.is_initialized() else socket.gethostname()
    return f"{host}:{os.getpid()}"


def run_chunk(spec, runs):
    return [run_one(spec, run) for run in runs]


def read_results(path):
    """A results.parquet as a DataFrame, read on this thread: Arrow's reading threads can still be running
    at the interpreter's exit and abort it ("terminate called without an active exception", apache/arrow#34314:
    4 of 40 igms-sweep runs under load here before this)."""
    import pandas as pd
    return pd.read_parquet(path, use_threads=False, pre_buffer=False)


def _read_done(path):
    return read_results(path).to_dict("records") if os.path.exists(path) else []


def _write(path, rows):
    import pandas as pd
    import pyarrow as pa
    frame = pd.DataFrame(sorted(rows, key=lambda r: r["run"]))
    for column in frame.columns:  # a column Arrow cannot type (values of mixed kinds) is kept as JSON text
        if frame[column].dtype == object:
            try:
                pa.array(frame[column], from_pandas=True)
            except (pa.ArrowInvalid, pa.ArrowTypeError):
                frame[column] = [None if v is None else json.dumps(v, default=plain) for v in frame[column]]
    tmp = path + ".tmp"
    frame.to_parquet(tmp, index=False)
    os.replace(tmp, path)


def run_sweep(spec, out="out/sweep", address=None, workers=None, progress=True, base_dir=".", serial=False, retry_failed=False,
              working_dir=None, checkpoint_s=5.0):
    """Runs the spec's runs not yet in OUT/results.parquet and writes it; returns its rows (a pandas DataFrame).
    serial: in this process, one after the other, without Ray (the reference a Ray sweep must match)."""
    import pandas as pd
    spec = load_spec(spec, base_dir)
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, RESULTS)
    runs = expand(spec)
    done = [r for r in _read_done(path) if not (retry_failed and isinstance(r.get("error"), str))]
    done_ids = {r["run_id"] for r in done}
    todo = [r for r in runs if r["run_id"] not in done_ids]
    rows = list(done)
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=len(runs), initial=len(runs) - len(todo), unit="run", desc="igms-sweep")
    last_write = time.monotonic()

    def finished(new_rows):
        nonlocal last_write
        rows.extend(new_rows)
        if bar:
            bar.update(len(new_rows))
        if time.monotonic() - last_write > checkpoint_s:
            _write(path, rows)
            last_write = time.monotonic()

    try:
        if serial:
            for run in todo:
                finished([run_one(spec, run)])
        elif todo:
            _run_on_ray(spec, todo, address, workers, working_dir, finished)
    finally:
        _write(path, rows)
        if bar:
            bar.close()
    return read_results(path)


def _run_on_ray(spec, todo, address, workers, working_dir, finished):
    import ray
    started = False
    if not ray.is_initialized():
        runtime_env = {"working_dir": working_dir} if working_dir else None
        if address:
            ray.init(address=address, runtime_env=runtime_env, log_to_driver=False, logging_level="ERROR")
        else:
            ray.init(num_cpus=workers or os.cpu_count(), include_dashboard=False, log_to_driver=False,
                     runtime_env=runtime_env, logging_level="ERROR")
        started = True
    try:
        slots = max(1, int(ray.cluster_resources().get("CPU", 1)))
        # Chunks of runs: a task per run costs Ray's overhead per run; 8 chunks a CPU keeps the cores busy and the bar moving.
        size = max(1, math.ceil(len(todo) / (8 * slots)))
        task = ray.remote(num_cpus=1)(run_chunk)
        spec_ref = ray.put(spec)
        pending = [task.remote(spec_ref, todo[i:i + size]) for i in range(0, len(todo), size)]
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            for ref in ready:
                finished(ray.get(ref))
    finally:
        if started:
            ray.shutdown()
