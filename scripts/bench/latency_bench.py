#!/usr/bin/python3
"""The paper's push and pull over a rehearsed network: igms-server on its realtime
clock, igms-relay between it and igms-haptic delaying (constant, and +-50 %
jitter) and dropping each direction, the logger on the server's side. Per case:
client rate, state age p99, largest force step (and cycles the 1 N bound cut),
whether the session stayed collision-free and reached the wall, and how far the
end-effector's path strayed from the zero-delay run's. Run it inside a private
network namespace (scripts/bench/latency_bench.sh does).
With --box, the environment instead: a scripted hand pushes a box out of the PUMA's
way on scenes/table_clear.yaml (the client's local model steps the contacts), and a
second table says where the box ended.
  scripts/bench/latency_bench.py [--quick | --box] [--seconds 7] [--out DIR] [--build build]"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import time

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import client_summary  # noqa: E402
from processes import stop_all  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES = {"push": "scenes/puma_obstacle.yaml", "pull": "scenes/puma_obstacle.yaml", "box": "scenes/table_clear.yaml"}
SCRIPTS = {"push": "scenes/paper_push.yaml", "pull": "scenes/paper_pull.yaml", "box": "scenes/table_clear_push.yaml"}


def cases(quick, box):
    if box:  # the hand pushes a box out of the arm's way (the client's local model steps the contacts)
        return [("box", d, j, 0) for d, j in ((0, 0), (5, 0), (10, 0), (20, 0), (20, 10), (50, 0))]
    if quick:
        return [("push", 0, 0, 0), ("push", 20, 10, 0), ("pull", 20, 10, 0), ("push", 5, 2.5, 0.1)]
    out = []
    for exp in ("push", "pull"):
        for d in (0, 0.5, 1, 2, 5, 10, 20, 50):
            out.append((exp, d, 0, 0))
            if d:
                out.append((exp, d, d / 2, 0))
        out.append((exp, 5, 0, 0.1))
    return out


def run_case(args, exp, delay, jitter, loss, port):
    server_url = f"udpm://239.255.76.67:{port}?ttl=0"
    client_url = f"udpm://239.255.76.67:{port + 1}?ttl=0"
    name = f"{exp}_d{delay:g}_j{jitter:g}_l{loss:g}"
    out = os.path.join(args.out, name)
    os.makedirs(out, exist_ok=True)
    log = os.path.join(out, "session.lcmlog")
    b = args.build
    procs = []
    try:
        procs.append(subprocess.Popen([f"{b}/tools/igms-logger", "-o", log, "--lcm-url", server_url, "-q",
                                       "--wait-session-s", "5", "-c", "IGMS_(SESSION_INFO|ROBOT_STATE|SERVER_STATUS)"],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        time.sleep(0.3)
        relay_err = open(os.path.join(out, "relay.log"), "w")
        procs.append(subprocess.Popen([f"{b}/tools/igms-relay", "--client-url", client_url, "--server-url",
                                       server_url, "--delay-ms", str(delay), "--jitter-ms", str(jitter),
                                       "--loss", str(loss), "--seed", "7"], stderr=relay_err))
        # The client waits for the server's first status and starts its script then: started after the
        # server, its script would begin wherever the arm had got to by the time the client was up (0.16 to
        # 0.42 s into the motion on an idle machine, later on a loaded one), and its pushes, aimed at the arm
        # where it is, would land on another part of the motion from run to run.
        client = subprocess.Popen([f"{b}/haptic_client/igms-haptic", "--scene", SCENES[exp], "--device",
                                   "scripted:" + SCRIPTS[exp], "--lcm-url", client_url, "--duration",
                                   str(args.seconds)] + args.client_args, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True)
        procs.append(client)
        time.sleep(0.3)
        procs.append(subprocess.Popen([f"{b}/server/igms-server", "--scene", SCENES[exp], "--lcm-url", server_url,
                                       "--clock", "realtime", "--quiet"], stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL))
        client_err = client.communicate(timeout=120)[1]
        open(os.path.join(out, "client.log"), "w").write(client_err)
    finally:
        stop_all(procs, pause=0.2)
    subprocess.run([f"{b}/tools/igms-replay", "export", log, os.path.join(out, "export")], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return name, out, client_err


def summarise(exp, delay, jitter, loss, out, client_log):
    rows = list(csv.DictReader(open(os.path.join(out, "export", "states.csv"))))
    scene = yaml.safe_load(open(os.path.join(out, "export", "scene.yaml")))
    t = np.array([float(r["t"]) for r in rows])
    hit = np.array([int(r["in_collision"]) for r in rows]) > 0
    ee = np.array([[float(r["ee_link.x"]), float(r["ee_link.y"]), float(r["ee_link.z"])] for r in rows])
    target = np.array(scene["trajectory"]["target"])
    force = np.linalg.norm(np.array([[float(r["fx"]), float(r["fy"]), float(r["fz"])] for r in rows]), axis=1)

    def peak(lo, hi):  # the largest force on the robot between two script times (s), N
        m = (t >= lo) & (t <= hi)
        return round(float(force[m].max()), 2) if m.any() else None
    c = client_summary.read(client_log)
    # When the client's script began, on the server's clock: the first step that took one of its inputs
    # (a path's delay after it was sent). The script's pushes aim at the arm where it is by then.
    used = np.array([int(r["input_seq"]) for r in rows]) > 0
    first_input = round(float(t[used][0]), 3) if used.any() else None
    start = first_input or 0.0
    b = re.search(r"igms-haptic: bus: accepted (\d+), refused (\d+)", client_log)  # a signed bus (IGMS_KEY_FILE)
    return {
        "experiment": exp, "delay_ms": delay, "jitter_ms": jitter, "loss": loss,
        "bus_accepted": int(b.group(1)) if b else None, "bus_refused": int(b.group(2)) if b else None,
        **{k: c[k] for k in ("cycles", "rate_hz", "max_force_step_N", "cut_to_bound", "state_age_p50_ms",
                             "state_age_p99_ms", "state_age_max_ms", "passivity_cycles")},
        "lowest_energy_mJ": None if c["lowest_energy_J"] is None else round(c["lowest_energy_J"] * 1000, 1),
        "server_lost": "server lost" in client_log, "first_input_s": first_input,
        "collision_free": not bool(hit.any()),
        # Where a run collides, what tells why: when it first did, how hard each of the paper's two pushes
        # pressed, and the retreat between them (paper_push.yaml's times from the script's first input:
        # 0.35-1.0 s, 1.35-2.2 s; the retreat 1.0-1.35 s).
        "first_collision_s": round(float(t[hit][0]), 3) if hit.any() else None,
        "push_peaks_N": [peak(start + 0.35, start + 1.0), peak(start + 1.35, start + 2.2)],
        "retreat_peak_N": peak(start + 1.0, start + 1.35),
        "reached_wall": bool((np.linalg.norm(ee - target, axis=1) <= 0.01).any()),
        "t": t.tolist(), "ee": ee.tolist(),
        # A box push: where box_b ended (the states carry every body as a link).
        "box_end": [float(rows[-1]["box_b." + c]) for c in "xyz"] if "box_b.x" in rows[0] else None,
    }


def shape_deviation(a, b):
    """Largest distance from a point of either end-effector path to the other path (Hausdorff, 5 ms samples), m:
    how far the path strayed, whatever the timing."""
    pa, pb = np.array(a["ee"])[::5], np.array(b["ee"])[::5]
    d = np.linalg.norm(pa[:, None, :] - pb[None, :, :], axis=2)
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def deviation(a, b):
    """Largest distance between the two end-effector paths at the same simulated times, m."""
    ta, tb = np.round(np.array(a["t"]) * 1000).astype(int), np.round(np.array(b["t"]) * 1000).astype(int)
    common, ia, ib = np.intersect1d(ta, tb, return_indices=True)
    if not len(common):
        return None
    return float(np.linalg.norm(np.array(a["ee"])[ia] - np.array(b["ee"])[ib], axis=1).max())


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="four cases (the test's), not the whole table")
    p.add_argument("--box", action="store_true",
                   help="the environment instead: a hand pushes a box out of the arm's way (scenes/table_clear.yaml)")
    p.add_argument("--seconds", type=float, default=7.0)
    p.add_argument("--out", default="out/latency_bench")
    p.add_argument("--build", default=os.environ.get("IGMS_BUILD", "build"))
    p.add_argument("--port", type=int, default=7830)
    p.add_argument("--json", help="write the results here too")
    p.add_argument("client_args", nargs="*", help="after --: more igms-haptic options")
    args = p.parse_args()
    os.chdir(ROOT)
    results, zero = [], {}
    for i, (exp, d, j, l) in enumerate(cases(args.quick, args.box)):
        name, out, log = run_case(args, exp, d, j, l, args.port + 2 * (i % 20))
        r = summarise(exp, d, j, l, out, log)
        if d == 0 and j == 0 and l == 0:
            zero[exp] = r
        r["deviation_mm"] = round(deviation(r, zero[exp]) * 1000, 1) if exp in zero else None
        r["shape_deviation_mm"] = round(shape_deviation(r, zero[exp]) * 1000, 1) if exp in zero else None
        results.append(r)
        print(f"{exp:4} delay {d:>4g} ms jitter +-{j:<4g} loss {l:<4g}: {r['rate_hz']} Hz, state age p99 "
              f"{r['state_age_p99_ms']} ms, max force step {r['max_force_step_N']} N ({r['cut_to_bound']} cut), "
              f"collision-free {r['collision_free']}, reached the wall {r['reached_wall']}, "
              f"deviation {r['deviation_mm']} mm (path {r['shape_deviation_mm']} mm), server lost {r['server_lost']}, "
              f"lowest energy balance "
              f"{r['lowest_energy_mJ']} mJ, passivity controller {r['passivity_cycles']} cycles, first input taken at the "
              f"server's {r['first_input_s']} s", flush=True)
    print()
    print("| experiment | one-way delay | jitter | loss | client rate | state age p99 | largest force step "
          "(cycles cut to 1 N) | lowest energy balance (controller cycles) | collision-free | reached the wall | "
          "deviation from 0 ms: at equal times (path) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|---|---:|")
    for r in results:
        print(f"| {r['experiment']} | {r['delay_ms']:g} ms | ±{r['jitter_ms']:g} ms | {r['loss'] * 100:g} % | "
              f"{r['rate_hz']} Hz | {r['state_age_p99_ms']} ms | {r['max_force_step_N']:.3f} N "
              f"({r['cut_to_bound']}) | {r['lowest_energy_mJ']} mJ ({r['passivity_cycles']}) | "
              f"{'yes' if r['collision_free'] else 'no'} | "
              f"{'yes' if r['reached_wall'] else 'no'} | {r['deviation_mm']} mm ({r['shape_deviation_mm']} mm) |")
    if args.box:
        print()
        print("| one-way delay | jitter | box_b moved along x | box_b's y (the arm sweeps it along y) | on the table (z) |")
        print("|---:|---:|---:|---:|---:|")
        for r in results:
            x, y, z = r["box_end"] or (float("nan"),) * 3
            print(f"| {r['delay_ms']:g} ms | ±{r['jitter_ms']:g} ms | {(x - 0.42) * 1000:.1f} mm | {y * 1000:.1f} mm | "
                  f"{z:.4f} m |")
    if args.json:
        json.dump([{k: v for k, v in r.items() if k not in ("t", "ee")} for r in results], open(args.json, "w"),
                  indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
