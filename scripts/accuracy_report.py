#!/usr/bin/python3
"""Work-precision report from igms-accuracy's CSV: for each case a plot of log
error against log run time (each method a line, ODE on the same axes), the
convergence order of each method fitted on its smallest steps, and a Markdown
table; then, when given, the ODE replays of recorded sessions (igms-ode-ref
--json lines) and the stiff and extreme cases' table (igms-accuracy --extreme).
Usage: scripts/accuracy_report.py CSV OUT_DIR [--replays JSONL] [--extreme CSV]"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def replay_section(path):
    md = ["## Recorded sessions replayed on ODE (igms-ode-ref)", "",
          "Each recorded igms session (1 ms, the server's integrator) replayed in ODE dWorldStep with the torques, "
          "user forces and damping igms applied. Open loop, the deviation grows with the arm's own instability, so "
          "the first simulated second is the figure; tracking adds the scene's PD gains on ODE's deviation from the "
          "recorded run, and the size of that correction against the recorded torque measures the disagreement.", "",
          "| session | mode | link origins max (m) | first second (m) | joints max (rad) | correction / torque (rms) "
          "| ODE cost (s/s) |", "|---|---|---:|---:|---:|---:|---:|"]
    for line in open(path):
        r = json.loads(line)
        first = r["link_max_by_second"][0] if r["link_max_by_second"] else float("nan")
        corr = f"{r['correction_rms'] / r['tau_rms']:.2g}" if r["tracking"] else ""
        md.append(f"| {os.path.basename(r['log'])} | {'tracking' if r['tracking'] else 'open loop'} | "
                  f"{r['link_max']:.3g} | {first:.3g} | {r['q_max']:.3g} | {corr} | {r['wall_s_per_s']:.3g} |")
    return md + [""]


def extreme_section(path):
    rows = list(csv.DictReader(open(path)))
    failed = sum(r["pass"] != "pass" for r in rows)
    md = ["## Stiff and extreme cases (igms-accuracy --extreme)", "",
          f"{len(rows)} rows, {failed} failed. Each row states its own criterion; the stress test "
          "`extreme_cases_test` asserts them all.", "",
          "| case | method | criterion | figure | result |", "|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['case']} | {r['method']} | {r['criterion']} | {r['figure']} | {r['pass']} |")
    return md + [""]


def main():
    path, out = sys.argv[1], sys.argv[2]
    extra = dict(zip(sys.argv[3::2], sys.argv[4::2]))
    os.makedirs(out, exist_ok=True)
    rows = list(csv.DictReader(open(path)))
    cases = sorted({r["case"] for r in rows}, key=lambda c: [r["case"] for r in rows].index(c))
    methods = sorted({r["method"] for r in rows}, key=lambda m: [r["method"] for r in rows].index(m))
    md = ["# igms accuracy: error against run time", "",
          f"From `{os.path.basename(path)}` (igms-accuracy). Error: the largest joint-space error (rad; for a floating "
          "base also m and rad of the base) against igms RK4 at 1/64 ms. Cost: wall seconds per simulated second, "
          "this machine (2 cores, noisy). Order: slope of log error against log h on the smallest steps that are "
          "above round-off (1e-9). n/a: not conserved in that case (energy with damping, momentum under gravity or "
          "on a fixed base), or no order (the method does not converge there).", ""]
    fig, axes = plt.subplots(1, len(cases), figsize=(5 * len(cases), 4.5), squeeze=False)
    for ax, case in zip(axes[0], cases):
        md += [f"## {case}", "", "| method | order | error at 1 ms (rad) | end-effector error at 1 ms (m) | "
               "energy drift at 1 ms | linear / angular momentum drift at 1 ms | cost at 1 ms (s/s) |",
               "|---|---:|---:|---:|---:|---:|---:|"]
        for m in methods:
            rs = [r for r in rows if r["case"] == case and r["method"] == m and r["diverged"] == "0"]
            h = np.array([float(r["h_ms"]) for r in rs])
            e = np.array([float(r["q_max"]) for r in rs])
            cost = np.array([float(r["wall_s_per_sim_s"]) for r in rs])
            ok = np.isfinite(e) & (e > 1e-9) & (e < 1.0)  # above round-off, below saturation
            order = float("nan")
            if ok.sum() >= 3:
                sel = np.argsort(h[ok])[:4]
                order = np.polyfit(np.log(h[ok][sel]), np.log(e[ok][sel]), 1)[0]
            style = "--" if m.startswith("ode") else "-"
            good = np.isfinite(e) & (e > 0)
            ax.loglog(cost[good], e[good], style + "o", ms=3, label=m)
            one = [r for r in rs if abs(float(r["h_ms"]) - 1.0) < 1e-9]
            if one:
                r = one[0]
                def num(x, fmt):
                    v = float(x)
                    return "n/a" if math.isnan(v) else format(v, fmt)
                md.append(f"| {m} | {num(order, '.2f')} | {num(r['q_max'], '.3g')} | {num(r['ee_max'], '.3g')} | "
                          f"{num(r['energy_drift'], '.3g')} | {num(r['linear_momentum_drift'], '.2g')} / "
                          f"{num(r['angular_momentum_drift'], '.2g')} | {num(r['wall_s_per_sim_s'], '.3g')} |")
            else:
                md.append(f"| {m} | {order:.2f} | diverged | | | | |")
        md.append("")
        ax.set_title(case)
        ax.set_xlabel("wall seconds per simulated second")
        ax.set_ylabel("max joint error (rad)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out, f"work_precision.{ext}"), dpi=100)
    md += ["![work-precision](work_precision.png)", ""]
    if "--replays" in extra:
        md += replay_section(extra["--replays"])
    if "--extreme" in extra:
        md += extreme_section(extra["--extreme"])
    open(os.path.join(out, "accuracy.md"), "w").write("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()
