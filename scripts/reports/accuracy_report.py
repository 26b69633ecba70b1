#!/usr/bin/python3
"""Work-precision report from igms-accuracy's CSV: for each case a plot of log
error against log run time (each method a line, ODE on the same axes), the
convergence order of each method fitted on its smallest steps, and a Markdown
table; then, when given, the ODE replays of recorded sessions (igms-ode-ref
--json lines) and the stiff and extreme cases' table (igms-accuracy --extreme).
With --peers (scripts/reports/accuracy_peers.py's mujoco.csv and peers.json beside it)
MuJoCo's integrators share the axes and tables, and with --truths the
independent truth's agreement with igms's own heads each case.
--ensemble (igms-accuracy --ensemble-csv) gives the chaotic cases' medians and
ranges, --stability (igms-accuracy --stiffness --csv) the stability table.
Usage: scripts/reports/accuracy_report.py CSV OUT_DIR [--replays JSONL] [--extreme CSV] [--peers CSV] [--truths CSV]
                                  [--ensemble CSV] [--stability CSV]"""
import csv
import json
import math
import os
import platform
import subprocess
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


def num(x, fmt):
    v = float(x)
    return "n/a" if math.isnan(v) else format(v, fmt)


HAPTIC_METHODS = ["semi_implicit_euler", "rk4", "linearly_implicit", "ode_worldstep", "ode_quickstep",
                  "mujoco_euler", "mujoco_implicit", "mujoco_implicitfast", "mujoco_rk4"]


def haptic_section(rows, truths_path):
    truths = {r["case"]: r for r in csv.DictReader(open(truths_path))}
    cases = [c for c in truths if c.startswith("puma_pull") or c.startswith("puma_push")]
    if not cases:
        return []
    md = ["## A hand on the PUMA at 1 ms: where each method stands", "",
          "The PUMA released under gravity with a hand held still on it for 1.024 s, through the server's own step: "
          "the pull (eq. 4) an uncapped spring from the end effector to a device point 5 cm away, the push (eq. 3) "
          "the device tip 5 mm into the forearm, which falls onto it. k from a PHANToM's 0.4 N/mm to 32 N/mm. "
          "k h^2/m: at 1 ms, m the arm's effective mass at the hand (at q0) in its lightest direction for the pull "
          "(the spring acts in all three), along the contact normal for the push. "
          "Each cell: the largest joint error (rad) against the truth, and the energy the method injects (+) or "
          "removes (-) per second (W; kinetic + gravity + the spring's; the undamped truth keeps it, the damped "
          "truth's own rate is given). Truth: the independent one (DOP853 on Pinocchio's ABA with eq. 4's force, or "
          "eq. 3's written anew on the forearm's cylinder as Pinocchio reads it from the URDF). MuJoCo: the "
          "undamped pull as a zero-length spatial tendon (the same force); not for the damped pull (a tendon's "
          "damping acts along the line only) nor the push (its soft contact is another model). LI per step: the "
          "linearly-implicit scheme's amplitude factor per step on that spring, 1/sqrt(1 + k h^2/m), and per period "
          "of the spring's own oscillation: its numerical damping.", ""]
    present = [m for m in HAPTIC_METHODS if any(r["method"] == m for r in rows)]
    md.append("| case | k h^2/m | truth (W) | LI per step / per period | " + " | ".join(present) + " |")
    md.append("|---|---:|---:|---:|" + "---:|" * len(present))
    for case in cases:
        t = truths[case]
        a = float(t["k_h2_over_m_at_1ms"])
        per_step = 1 / math.sqrt(1 + a)
        per_period = per_step ** (2 * math.pi / math.sqrt(a))
        cells = []
        for m in present:
            r = [x for x in rows if x["case"] == case and x["method"] == m and abs(float(x["h_ms"]) - 1.0) < 1e-9]
            if not r:
                cells.append("")
            elif r[0]["diverged"] != "0" or not math.isfinite(float(r[0]["q_max"])):
                cells.append("diverged")
            else:
                cells.append(f"{float(r[0]['q_max']):.2g} / {float(r[0]['energy_rate_w']):+.2g}")
        md.append(f"| {case} | {a:.3g} | {float(t['truth_energy_rate_w']):+.2g} | {per_step:.3f} / {per_period:.2g} | " +
                  " | ".join(cells) + " |")
    return md + [""]


def ensemble_section(path):
    rows = list(csv.DictReader(open(path)))
    if not rows:
        return []
    md = ["## Ensembles at 1 ms: median [min, max] over perturbed starts", "",
          f"{rows[0]['starts']} starts per case, q0 + U(-0.01, 0.01) rad on every joint (seeded), each against its own "
          "truth (igms RK4 at 1/64 ms, which the nominal start's independent truth confirms; see each case). "
          "Energy drift: max |E(t) - E(0)| / |E(0)|.", "",
          "| case | method | joint error (rad) | end-effector error (m) | energy drift | energy rate (W) | diverged |",
          "|---|---|---|---|---|---|---:|"]

    def spread(r, f, fmt=".2g"):
        if math.isnan(float(r[f + "_median"])):
            return "n/a"
        return f"{float(r[f + '_median']):{fmt}} [{float(r[f + '_min']):{fmt}}, {float(r[f + '_max']):{fmt}}]"
    for r in rows:
        md.append(f"| {r['case']} | {r['method']} | {spread(r, 'q_max')} | {spread(r, 'ee_max')} | "
                  f"{spread(r, 'energy_drift')} | {spread(r, 'energy_rate_w', '+.2g')} | {r['diverged']} |")
    return md + [""]


def stability_section(path):
    rows = list(csv.DictReader(open(path)))
    md = ["## Stability: amplitude factor per step on a spring and damper", "",
          "0.1 kg at 1 ms (`igms-accuracy --stiffness`): each scheme's one-step matrix, built by running igms's own "
          "integrator from the two unit states, and its spectral radius (> 1: the amplitude grows every step, "
          "unstable). zeta: the damping ratio b / (2 sqrt(k m)). Linearly implicit, theory: 1/sqrt(1 + k h^2/m), "
          "undamped. Stable does not mean accurate: at k h^2/m = 100 the linearly-implicit scheme keeps 0.0995 of "
          "the amplitude per step.", ""]
    limits = [r for r in rows if r["k_h2_m"] == "limit"]
    for r in limits:
        li = float(r["linearly_implicit"])
        md.append(f"- zeta {float(r['zeta']):.1f}: stability limit of k h^2/m: semi-implicit Euler "
                  f"{float(r['semi_implicit_euler']):.4f}, RK4 {float(r['rk4']):.4f}, linearly implicit "
                  f"{'none up to 1e4' if math.isinf(li) else format(li, '.4f')}")
    md += ["", "| k h^2/m | zeta | semi-implicit Euler | RK4 | linearly implicit | linearly implicit, theory |",
           "|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if r["k_h2_m"] == "limit":
            continue
        cells = []
        for m in ("semi_implicit_euler", "rk4", "linearly_implicit"):
            x = float(r[m])
            cells.append(f"**{x:.4f}**" if x > 1 + 1e-12 else f"{x:.4f}")
        md.append(f"| {float(r['k_h2_m']):.4g} | {float(r['zeta']):.1f} | " + " | ".join(cells) +
                  f" | {num(r['linearly_implicit_theory'], '.4f')} |")
    return md + [""]


def cpu():
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def truth_lines(path, case, peers):
    rows = [r for r in csv.DictReader(open(path)) if r["case"] == case]
    if not rows:
        return []
    r = rows[0]
    if r["reference"] == "none":
        return [f"Truth: igms's RK4 at 1/64 ms (step halving moves it by {float(r['igms_truth_halving_q_max']):.1e} "
                "rad). No independent truth for this case.", ""]
    md = [f"Truth: {r['reference']} (against itself at a 10x tighter tolerance: "
          f"{float(r['reference_self_check_q_max']):.1e} rad). igms's own truth, RK4 at 1/64 ms (step halving: "
          f"{float(r['igms_truth_halving_q_max']):.1e} rad), agrees with it to "
          f"{float(r['igms_truth_vs_reference_q_max']):.1e} rad and {float(r['igms_truth_vs_reference_ee_max']):.1e} m "
          "at the end effector. Every error below is against the independent truth.", ""]
    info = peers.get("cases", {}).get(case)
    if info:
        restored = ", ".join(info["restored_inertias"]) or "none"
        md.append(f"MuJoCo's model: the URDF's exact masses and inertias written back after compiling (changed by "
                  f"its compiler: {restored}); its joint-space inertia matrix and bias forces at q0 agree with "
                  f"Pinocchio's to {info['H_relative_difference']:.0e} and {info['bias_relative_difference']:.0e} "
                  "(relative).")
    return md + [""]


def main():
    path, out = sys.argv[1], sys.argv[2]
    extra = dict(zip(sys.argv[3::2], sys.argv[4::2]))
    os.makedirs(out, exist_ok=True)
    rows = list(csv.DictReader(open(path)))
    peers = {}
    if "--peers" in extra:
        rows += list(csv.DictReader(open(extra["--peers"])))
        info = os.path.join(os.path.dirname(extra["--peers"]), "peers.json")
        peers = json.load(open(info)) if os.path.exists(info) else {}
    independent = "--truths" in extra
    cases = sorted({r["case"] for r in rows}, key=lambda c: [r["case"] for r in rows].index(c))
    methods = sorted({r["method"] for r in rows}, key=lambda m: [r["method"] for r in rows].index(m))
    md = ["# igms accuracy: error against run time", "",
          f"From `{os.path.basename(path)}` (igms-accuracy)" +
          (f" and MuJoCo {peers.get('mujoco', '')} (scripts/reports/accuracy_peers.py: Euler, implicit, implicitfast, RK4 "
           "from the same URDF and start, contacts and limits off)" if peers else "") +
          ". Error: the largest joint-space error (rad; for a floating base also m and rad of the base) against " +
          ("the independent truth (SciPy DOP853 on Pinocchio's ABA)" if independent else "igms RK4 at 1/64 ms") +
          "; RMS over joints and samples beside it. Energy drift: max |E(t) - E(0)| / |E(0)| (mechanical energy, "
          "over the run). ODE QuickStep: 100 iterations, over-relaxation 1.3 (its default), constraint order "
          f"seeded. Cost: wall seconds per simulated second, median of up to 3 runs [min, max], on {cpu()}, "
          "2 cores, noisy VM; igms and ODE in C++ at -O3 (CMake Release), MuJoCo's wheel through its C rollout. "
          "Order: slope of log error against log h on the smallest steps that are "
          "above round-off (1e-9). n/a: not conserved in that case (energy with damping, momentum under gravity or "
          "on a fixed base), or no order (the method does not converge there).", ""]
    ncols = min(4, len(cases))
    nrows = (len(cases) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(5 * ncols, 4.5 * nrows), squeeze=False)
    for ax in axes.flat[len(cases):]:
        ax.set_visible(False)
    for ax, case in zip(axes.flat, cases):
        md += [f"## {case}", ""]
        if independent:
            md += truth_lines(extra["--truths"], case, peers)
        md += ["| method | order | error at 1 ms (rad) | RMS error at 1 ms (rad) | per joint at 1 ms | "
               "end-effector error at 1 ms (m) | energy drift at 1 ms | linear / angular momentum drift at 1 ms | "
               "cost at 1 ms (s/s) [min, max] |",
               "|---|---:|---:|---:|---|---:|---:|---:|---:|"]
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
            style = "--" if m.startswith("ode") else ":" if m.startswith("mujoco") else "-"
            good = np.isfinite(e) & (e > 0)
            ax.loglog(cost[good], e[good], style + "o", ms=3, label=m)
            one = [r for r in rs if abs(float(r["h_ms"]) - 1.0) < 1e-9]
            if one:
                r = one[0]
                spread = (f" [{num(r['wall_s_per_sim_s_min'], '.3g')}, {num(r['wall_s_per_sim_s_max'], '.3g')}]"
                          if r.get("wall_s_per_sim_s_min") else "")
                joints = " ".join(f"{float(x):.1g}" for x in r.get("q_max_per_joint", "").split(";") if x)
                if len(joints.split()) > 8:
                    joints = f"{len(joints.split())} joints"
                md.append(f"| {m} | {num(order, '.2f')} | {num(r['q_max'], '.3g')} | {num(r['q_rms'], '.3g')} | "
                          f"{joints} | {num(r['ee_max'], '.3g')} | "
                          f"{num(r['energy_drift'], '.3g')} | {num(r['linear_momentum_drift'], '.2g')} / "
                          f"{num(r['angular_momentum_drift'], '.2g')} | {num(r['wall_s_per_sim_s'], '.3g')}{spread} |")
            else:
                md.append(f"| {m} | {num(order, '.2f')} | diverged | | | | | | |")
        md.append("")
        ax.set_title(case)
        ax.set_xlabel("wall seconds per simulated second")
        ax.set_ylabel("max joint error (rad)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out, f"work_precision.{ext}"), dpi=72)
    md += ["![work-precision](work_precision.png)", ""]
    if independent:
        md += haptic_section(rows, extra["--truths"])
    if "--ensemble" in extra:
        md += ensemble_section(extra["--ensemble"])
    if "--stability" in extra:
        md += stability_section(extra["--stability"])
    if "--replays" in extra:
        md += replay_section(extra["--replays"])
    if "--extreme" in extra:
        md += extreme_section(extra["--extreme"])
    open(os.path.join(out, "accuracy.md"), "w").write("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()
