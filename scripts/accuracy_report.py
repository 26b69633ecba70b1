#!/usr/bin/python3
"""Work-precision report from igms-accuracy's CSV: for each case a plot of log
error against log run time (each method a line, ODE on the same axes), the
convergence order of each method fitted on its smallest steps, and a Markdown
table. Usage: scripts/accuracy_report.py CSV OUT_DIR"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    path, out = sys.argv[1], sys.argv[2]
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
    open(os.path.join(out, "accuracy.md"), "w").write("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()
