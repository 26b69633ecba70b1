#!/usr/bin/python3
"""Where the push's virtual coupling stays stable: a grid of coupling stiffness k and damping b, each run
over the real bus (igms-server on its realtime clock, igms-relay delaying each direction, igms-haptic at
1 kHz with the passivity controller off so that its observer reports the coupling's own energy balance),
the simulated hand pushing the 1 kg box of scenes/truth/box_push.yaml at 5 cm/s. A point is stable when
the observer's balance never goes below its tolerance (25 mJ: energy made by the loop, not put in by the
hand), the force does not oscillate more late in the push than early (no growing oscillation), and its
ripple late in the push is within 5 % of mu m g (no limit cycle). Points
under the Colgate-Schenkel line b = k T / 2 are refused at the scene's load and are drawn as such.
Run inside a private network namespace (scripts/netns_run.sh). Writes DIR/stability.json and the chart.
  scripts/bench/coupling_stability.py [--delays 0,5,20] [--k 1000,...] [--b 1,...] [--out DIR] [--plot PNG]"""
import argparse
import json
import os
import re
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import haptic_truth  # noqa: E402  (the runs over the bus, the record's columns)

ROOT = haptic_truth.ROOT
TOLERANCE_J = 0.025
RATE_HZ = 1000.0
MU_M_G = 0.5 * 1.0 * 9.81  # the push's steady force
RIPPLE = 0.05  # of it: the truth suite's bound on the ripple


def scene_with(k, b, out):
    scene = yaml.safe_load(open(os.path.join(haptic_truth.TRUTH, "box_push.yaml")))
    scene["interaction"]["push"].pop("k_p", None)
    scene["interaction"]["coupling"] = {"k": float(k), "b": float(b)}
    path = os.path.join(out, f"box_push_k{k:g}_b{b:g}.yaml")
    yaml.safe_dump(scene, open(path, "w"))
    return path


def run_point(args, k, b, delay):
    name = f"k{k:g}_b{b:g}"
    case = {"name": name, "scene": scene_with(k, b, args.out), "scripts": {"hand": "box_push_hand.yaml"}}
    s, log, _ = haptic_truth.over_bus(args.build, case, "hand", delay, args.out, args.port,
                                      client_args=["--no-passivity"], return_log=True)
    m = re.search(r"lowest energy balance ([-\d.]+) J", log)
    lowest = float(m.group(1)) if m else float("nan")
    fx = -s["force"][:, 0]
    t = s["t"]
    early = fx[(t >= 1.2) & (t <= 2.2)].std()
    late = fx[(t >= 2.5) & (t <= 3.5)].std()
    growing = late > 1.5 * early + 0.01 * MU_M_G or np.abs(fx).max() >= 11.9  # 12 N: the device's limit
    ringing = late > RIPPLE * MU_M_G  # a limit cycle: it does not grow, but it does not die either
    return {"k": k, "b": b, "delay_ms": delay, "lowest_energy_J": lowest, "ripple_early_N": float(early),
            "ripple_late_N": float(late), "growing": bool(growing), "ringing": bool(ringing),
            "stable": bool(lowest >= -TOLERANCE_J and not growing and not ringing)}


def plot(results, delays, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(delays), figsize=(4.2 * len(delays), 3.8), sharey=True)
    for ax, d in zip(np.atleast_1d(axes), delays):
        ks = np.logspace(2.5, 5.5, 50)
        ax.plot(ks, ks / (2 * RATE_HZ), "k--", lw=1, label="b = k T / 2 (refused below)")
        for r in results:
            if r["delay_ms"] != d:
                continue
            style = ("o", "tab:green") if r.get("stable") else ("x", "tab:red") if "stable" in r else ("s", "0.6")
            ax.plot(r["k"], r["b"], style[0], color=style[1], ms=7, mfc="none" if style[0] == "s" else None)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("coupling stiffness k (N/m)")
        ax.set_title(f"{d:g} ms one way")
        ax.grid(True, which="both", alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("coupling damping b (N s/m)")
    handles = [plt.Line2D([], [], ls="", marker="o", color="tab:green", label="stable"),
               plt.Line2D([], [], ls="", marker="x", color="tab:red", label="unstable"),
               plt.Line2D([], [], ls="", marker="s", color="0.6", mfc="none", label="refused at load"),
               plt.Line2D([], [], ls="--", color="k", label="b = k T / 2")]
    fig.legend(handles=handles, loc="lower center", ncol=4, frameon=False)
    fig.suptitle("The push's virtual coupling at 1 kHz: simulated hand pushing a 1 kg box")
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(path, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--delays", default="0,5,20")
    p.add_argument("--k", default="1000,3000,10000,30000,100000")
    p.add_argument("--b", default="1,3,10,30,100,300")
    p.add_argument("--build", default=os.environ.get("IGMS_BUILD", os.path.join(ROOT, "build")))
    p.add_argument("--out", default=os.path.join(ROOT, "out", "coupling_stability"))
    p.add_argument("--port", type=int, default=7894)
    p.add_argument("--plot", default=os.path.join(ROOT, "docs", "client", "coupling_stability.png"))
    args = p.parse_args()
    args.build = os.path.abspath(args.build)
    os.makedirs(args.out, exist_ok=True)
    delays = [float(d) for d in args.delays.split(",")]
    results = []
    for d in delays:
        for k in [float(x) for x in args.k.split(",")]:
            for b in [float(x) for x in args.b.split(",")]:
                if b < k / (2 * RATE_HZ):
                    results.append({"k": k, "b": b, "delay_ms": d, "refused": True})
                    continue
                r = run_point(args, k, b, d)
                results.append(r)
                print(f"{d:4g} ms  k {k:8g}  b {b:6g}: {'stable  ' if r['stable'] else 'UNSTABLE'} lowest balance "
                      f"{r['lowest_energy_J'] * 1e3:8.2f} mJ, ripple {r['ripple_early_N']:.4f} -> "
                      f"{r['ripple_late_N']:.4f} N", flush=True)
    json.dump(results, open(os.path.join(args.out, "stability.json"), "w"), indent=1)
    os.makedirs(os.path.dirname(os.path.abspath(args.plot)), exist_ok=True)
    plot(results, delays, args.plot)
    print(f"wrote {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
