#!/usr/bin/env python3
"""The igms module's costs from Python, each beside a peer in the same run (medians; ratios printed):

  1. sim.step() called from Python on the PUMA scene (puma_wall.yaml, linearly implicit) against the same
     step timed in C++ by igms-step-bench: the call's overhead.
  2. model.rnea(q, v, a) on the UR5 against pinocchio.rnea, both called from Python in .venv-peers.
  3. Two simulations stepped on two threads against the same two on one (step(n) releases the GIL).
  4. A 200-run sweep of box_slide over friction and initial speed on a local Ray against the serial loop:
     bit-identical rows, the speed-up with and without Ray's start.

  PYTHONPATH=build/python .venv/bin/python scripts/bench/python_bench.py [--quick] [--json FILE]
Run from the repository's root after scripts/setup/setup.sh (and scripts/setup/peer_env.sh for part 2); the sweep's
local Ray runs inside scripts/netns_run.sh."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

import igms

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
UR5 = os.path.join(ROOT, "third_party/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf")
STEP_ROW = "PUMA, trajectory + computed torque + FD, linearly_implicit"


def median_per_call(fn, calls, batches):
    """fn() timed in batches of `calls` calls: the median batch's time per call, s."""
    times = []
    for _ in range(batches):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        times.append((time.perf_counter() - t0) / calls)
    return statistics.median(times)


def step_overhead(quick):
    steps = 3000 if quick else 20000
    out = subprocess.run([os.path.join(ROOT, "build/bench/igms-step-bench"), "--only", STEP_ROW, "--steps", str(steps)],
                         capture_output=True, text=True, check=True).stdout
    cpp_us = float(out.split("median")[1].split()[0])
    scene = igms.Scene.load(os.path.join(ROOT, "scenes/puma_wall.yaml"))
    per_call, amortised = [], []
    for _ in range(3):  # each a fresh simulation over the same steps as the C++ row
        sim = igms.Simulation(scene)
        per_call.append(median_per_call(sim.step, 1000, steps // 1000))
        sim = igms.Simulation(scene)
        t0 = time.perf_counter()
        sim.step(steps)
        amortised.append((time.perf_counter() - t0) / steps)
    py_us, batch_us = 1e6 * statistics.median(per_call), 1e6 * statistics.median(amortised)
    print(f"1. sim.step() on puma_wall: Python {py_us:.3f} us a call, C++ {cpp_us:.3f} us (igms-step-bench): "
          f"+{py_us - cpp_us:.3f} us a call (goal <= 0.5); sim.step({steps}) {batch_us:.3f} us a step")
    return {"python_step_us": py_us, "cpp_step_us": cpp_us, "overhead_us": py_us - cpp_us, "step_n_us": batch_us}


RNEA_PEER = r"""
import json, statistics, sys
import numpy as np
import pinocchio as pin
import igms
from python_bench import median_per_call
path, calls, batches = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
pm = pin.buildModelFromUrdf(path); pd = pm.createData()
im = igms.Model.from_urdf(path)
assert (pm.nq, pm.nv) == (im.nq, im.nv)
rng = np.random.default_rng(1)
q, v, a = (rng.uniform(-1, 1, im.nv) for _ in range(3))
err = float(np.max(np.abs(im.rnea(q, v, a) - pin.rnea(pm, pd, q, v, a))))
rounds = []
for _ in range(3):  # interleaved
    rounds.append((median_per_call(lambda: im.rnea(q, v, a), calls, batches),
                   median_per_call(lambda: pin.rnea(pm, pd, q, v, a), calls, batches)))
print(json.dumps({"igms_us": 1e6 * statistics.median(r[0] for r in rounds),
                  "pinocchio_us": 1e6 * statistics.median(r[1] for r in rounds), "max_difference": err}))
"""


def rnea_against_pinocchio(quick):
    peers = os.path.join(ROOT, ".venv-peers/bin/python")
    if not os.path.exists(peers) or not os.path.exists(UR5):
        print("2. rnea against pinocchio: skipped (needs .venv-peers: scripts/setup/peer_env.sh; and scripts/setup/fetch_robots.sh)")
        return None
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "build/python") + os.pathsep + os.path.dirname(__file__))
    r = json.loads(subprocess.run([peers, "-c", RNEA_PEER, UR5, "2000", "10" if quick else "50"], env=env,
                                  capture_output=True, text=True, check=True).stdout)
    print(f"2. rnea on the UR5 from Python: igms {r['igms_us']:.3f} us, pinocchio {r['pinocchio_us']:.3f} us: "
          f"ratio {r['igms_us'] / r['pinocchio_us']:.2f} (goal < 1); largest difference {r['max_difference']:.1e}")
    return r


def threads(quick):
    scene = igms.Scene.load(os.path.join(ROOT, "scenes/box_tower.yaml"))
    n = 500 if quick else 2000
    ratios = []
    for _ in range(3):
        a, b = igms.Simulation(scene), igms.Simulation(scene)
        t0 = time.perf_counter()
        a.step(n)
        b.step(n)
        one = time.perf_counter() - t0
        c, d = igms.Simulation(scene), igms.Simulation(scene)
        workers = [threading.Thread(target=s.step, args=(n,)) for s in (c, d)]
        t0 = time.perf_counter()
        for w in workers:
            w.start()
        for w in workers:
            w.join()
        two = time.perf_counter() - t0
        assert np.array_equal(c.q, a.q) and np.array_equal(d.q, b.q)
        ratios.append(one / two)
    r = statistics.median(ratios)
    print(f"3. two box_tower simulations, {n} steps each: two threads {r:.2f}x one thread (goal >= 1.8; "
          f"runs {', '.join(f'{x:.2f}' for x in ratios)}); the same bits")
    return {"thread_speedup": r, "runs": ratios}


SWEEP = {"scene": "scenes/box_slide.yaml", "seconds": 2.0, "metrics": ["final_pose", "max_penetration", "max_contacts"],
         "grid": {"materials.wood.friction": [round(0.1 + 0.05 * k, 2) for k in range(20)],
                  "bodies[box].v": [[0.25 * (k + 1), 0, 0] for k in range(10)]}}


def sweep(quick):
    import ray
    from igms import sweeps
    workers = 2
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        serial = sweeps.run_sweep(SWEEP, os.path.join(tmp, "serial"), serial=True, progress=False, base_dir=ROOT)
        t_serial = time.perf_counter() - t0
        t0 = time.perf_counter()
        ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, logging_level="ERROR")
        t_start = time.perf_counter() - t0
        try:
            t0 = time.perf_counter()
            on_ray = sweeps.run_sweep(SWEEP, os.path.join(tmp, "ray"), progress=False, base_dir=ROOT)
            t_ray = time.perf_counter() - t0
        finally:
            ray.shutdown()
    a, b = serial.drop(columns=["duration_s", "worker"]), on_ray.drop(columns=["duration_s", "worker"])
    identical = all(np.array_equal(np.stack(a[c]) if a[c].dtype == object else a[c], np.stack(b[c]) if b[c].dtype == object
                                   else b[c]) for c in a.columns if c != "error") and a["error"].isna().all()
    print(f"4. a 200-run box_slide sweep: serial {t_serial:.2f} s, local Ray ({workers} workers) {t_ray:.2f} s "
          f"({t_serial / t_ray:.2f}x; goal >= 1.7), {t_ray + t_start:.2f} s with Ray's start "
          f"({t_serial / (t_ray + t_start):.2f}x); rows bit-identical: {identical}")
    return {"serial_s": t_serial, "ray_s": t_ray, "ray_start_s": t_start, "speedup": t_serial / t_ray,
            "speedup_with_start": t_serial / (t_ray + t_start), "identical": bool(identical)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps and batches")
    parser.add_argument("--json", help="write the figures here")
    args = parser.parse_args()
    os.chdir(ROOT)
    figures = {"step": step_overhead(args.quick), "rnea": rnea_against_pinocchio(args.quick),
               "threads": threads(args.quick), "sweep": sweep(args.quick)}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(figures, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
