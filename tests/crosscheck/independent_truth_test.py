#!/usr/bin/python3
"""The accuracy report's independent truth and MuJoCo, end to end, as
scripts/reports/accuracy.sh runs them (short cases): igms writes the cases, SciPy's
DOP853 on Pinocchio's ABA and MuJoCo run them in .venv-peers, and igms
measures against that truth. Asserted:
  - the independent truth agrees with igms's own (RK4 at 1/64 ms) to 1e-10 rad,
    and to 1e-7 on the push (eq. 3 written anew on the forearm's cylinder);
  - MuJoCo's model equals Pinocchio's (H and bias at q0, relative 1e-12);
  - the same scheme on the same equations gives the same error: igms RK4 and
    MuJoCo RK4, igms semi-implicit Euler and MuJoCo Euler (no damping there),
    to 1 %, and RK4's order is 4;
  - the ensemble's CSV holds median within [min, max] for every method.
Usage: independent_truth_test.py BUILD_DIR SOURCE_DIR"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from peer_checks import PeerCheck  # noqa: E402

suite = PeerCheck(sys.argv)
build, source, accuracy, python, check = suite.build, suite.source, suite.accuracy, suite.python, suite.check
cases = ["puma_swing", "tumble", "puma_pull_k8000", "puma_push_k2000"]
with_mujoco = cases[:3]  # the push's contact is another model in MuJoCo
with tempfile.TemporaryDirectory() as tmp:
    d = os.path.join(tmp, "cases")
    os.mkdir(d)
    common = ["--quick", "--duration", "0.256"]
    for c in cases:
        subprocess.run([accuracy, "--case", c, "--write-cases", d] + common, check=True)
    subprocess.run([python, os.path.join(source, "scripts", "reports", "accuracy_peers.py"), d, "--quick", "--repeats", "1"],
                   check=True)
    rows, truths, ensemble = [], {}, []
    for c in cases:
        out, t, e = (os.path.join(tmp, f"{c}.{x}.csv") for x in ("rows", "truth", "ensemble"))
        subprocess.run([accuracy, "--case", c, "--reference", d, "--truth-csv", t, "--csv", out, "--repeats", "1",
                        "--ensemble", "3", "--ensemble-csv", e] + common, check=True)
        rows += list(csv.DictReader(open(out)))
        truths.update({r["case"]: r for r in csv.DictReader(open(t))})
        ensemble += list(csv.DictReader(open(e)))
    rows += list(csv.DictReader(open(os.path.join(d, "mujoco.csv"))))
    peers = json.load(open(os.path.join(d, "peers.json")))

for c in cases:
    t = truths[c]
    check("DOP853" in t["reference"], f"{c}: the truth is the independent one ({t['reference']})")
    # igms's own RK4 at 1/64 ms steps over the push's contact onsets: 8 digits there
    check(float(t["igms_truth_vs_reference_q_max"]) < (1e-7 if "push" in c else 1e-10),
          f"{c}: igms's truth agrees with DOP853 on Pinocchio: {float(t['igms_truth_vs_reference_q_max']):.2e} rad")
    check(float(t["reference_self_check_q_max"]) < 1e-10,
          f"{c}: DOP853 against itself at 10x tighter tolerance: {float(t['reference_self_check_q_max']):.2e} rad")
    if c not in with_mujoco:
        continue
    info = peers["cases"][c]
    check(info["H_relative_difference"] < 1e-12 and info["bias_relative_difference"] < 1e-12,
          f"{c}: MuJoCo's H and bias equal Pinocchio's ({info['H_relative_difference']:.1e}, "
          f"{info['bias_relative_difference']:.1e})")


def err(case, method, h):
    r = [x for x in rows if x["case"] == case and x["method"] == method and abs(float(x["h_ms"]) - h) < 1e-9]
    return float(r[0]["q_max"])


for c in with_mujoco:
    for ours, theirs in (("rk4", "mujoco_rk4"), ("semi_implicit_euler", "mujoco_euler")):
        a, b = err(c, ours, 1.0), err(c, theirs, 1.0)
        check(abs(a - b) <= 0.01 * max(a, b), f"{c}: igms {ours} {a:.4g} rad, MuJoCo {theirs} {b:.4g} at 1 ms")
    o = math.log2(err(c, "mujoco_rk4", 4.0) / err(c, "mujoco_rk4", 2.0))  # above round-off on every case
    check(3.5 < o < 4.5, f"{c}: MuJoCo RK4's order against the independent truth: {o:.2f}")
check(len(ensemble) == 5 * len(cases), f"ensemble rows: {len(ensemble)}")
for r in ensemble:
    lo, med, hi = (float(r[f"q_max_{k}"]) for k in ("min", "median", "max"))
    check(r["starts"] == "3" and lo <= med <= hi and hi > 0, f"ensemble {r['case']} {r['method']}: "
          f"{med:.3g} [{lo:.3g}, {hi:.3g}]")
suite.finish("independent truth")
