#!/usr/bin/env python3
"""The contact section of the accuracy report: each contact case's error
against its analytic answer beside the run time per simulated second, for
igms, ODE's dWorldStep and MuJoCo's mj_step (Euler and implicit), as a table
and a work-precision plot. ODE's scene has no meshes: no ODE row for the mesh.

  contact_accuracy_report.py IGMS_ODE.csv MUJOCO.csv OUT_DIR
      IGMS_ODE.csv from igms-accuracy --contact --csv, MUJOCO.csv from
      scripts/bench/contact_peers.py --accuracy; writes OUT_DIR/contact.md and
      OUT_DIR/contact_work_precision.png.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES = [
    ("box_slide", "box sliding to a stop, mu 0.5, v0 1 m/s", "|stop - v0^2/(2 mu g)| (m)"),
    ("box_slope", "box on a 20 deg slope, mu 1 (must stick)", "creep after 0.5 s (m/s)"),
    ("sphere_roll", "sphere rolling down 15 deg", "|v(1 s) - (5/7) g sin th| / that"),
    ("ball_bounce", "ball dropped 1 m, e = 0.5", "|apex - e^2 m| / e^2 m"),
    ("free_top", "free top, 50 rad/s spin, 2 rad/s wobble, 10 s", "|E - E0| / E0"),
    ("ball_on_mesh", "3 cm ball resting on a mesh cube", "|rest height - r| (m)"),
]
ENGINES = [("igms", "igms", "C0", "o"), ("ode_dworldstep", "ODE dWorldStep", "C1", "s"),
           ("mujoco_euler", "MuJoCo mj_step (Euler, defaults)", "C2", "^"),
           ("mujoco_implicit", "MuJoCo mj_step (implicit)", "C3", "v")]
FLOOR = 1e-18  # errors at round-off are drawn here


def read(paths):
    rows = []
    for p in paths:
        with open(p) as f:
            rows += list(csv.DictReader(f))
    return rows


def main():
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    rows = read(sys.argv[1:3])
    out = sys.argv[3]
    os.makedirs(out, exist_ok=True)
    md = ["# Contact: error against run time", "",
          "Each case against its analytic answer; run time is the steps' wall time per simulated second "
          "(igms and ODE from C++, the median of 3 runs; MuJoCo through `mujoco.rollout`, the median of 3). "
          "Made by `scripts/reports/accuracy.sh` (`igms-accuracy --contact`, `scripts/bench/contact_peers.py --accuracy`, "
          "this script).", ""]
    fig, axes = plt.subplots(3, 2, figsize=(11, 12.5))
    for ax, (case, title, measure) in zip(axes.flat, CASES):
        md += [f"## {title}", "", f"error: {measure}", "",
               "| h (ms) | " + " | ".join(f"{label} error | s per s" for _, label, _, _ in ENGINES) + " |",
               "|---:|" + "---:|---:|" * len(ENGINES)]
        hs = sorted({float(r["h_ms"]) for r in rows if r["case"] == case})
        for h in hs:
            cells = []
            for engine, _, _, _ in ENGINES:
                r = next((r for r in rows if r["case"] == case and r["engine"] == engine and float(r["h_ms"]) == h),
                         None)
                cells += ["n/a", ""] if r is None else [f"{float(r['error']):.3g}", f"{float(r['wall_s_per_sim_s']):.3g}"]
            md.append(f"| {h:g} | " + " | ".join(cells) + " |")
        md.append("")
        for engine, label, color, marker in ENGINES:
            pts = sorted(((float(r["wall_s_per_sim_s"]), max(float(r["error"]), FLOOR), float(r["h_ms"]))
                          for r in rows if r["case"] == case and r["engine"] == engine and
                          not math.isnan(float(r["error"]))))
            if not pts:
                continue
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=marker, color=color, label=label)
            for x, y, h in pts:
                if h == 1.0:
                    ax.annotate("1 ms", (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7, color=color)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("run time per simulated second (s)")
        ax.set_ylabel(measure, fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    axes.flat[0].legend(fontsize=8)
    fig.suptitle(f"Contact cases: error against run time (errors below {FLOOR:g} drawn at {FLOOR:g})")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "contact_work_precision.png"), dpi=90)
    with open(os.path.join(out, "contact.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print(f"contact_accuracy_report: wrote {out}/contact.md and contact_work_precision.png")


if __name__ == "__main__":
    main()
