#!/usr/bin/python3
"""A free body spun near its intermediate axis (Dzhanibekov), as a user runs it: igms-scenario on a
scene (I = (1, 2, 3) kg m^2, w0 = (0.1, 5, 0.1) rad/s, zero gravity, a ground far below so contact is
possible, 20 s at 1 ms), its CSV's quaternions; the flips (the body's y axis turning through the
plane normal to the angular momentum, downward) against SciPy's DOP853 at 1e-12 on Euler's equations
and the orientation's kinematics (scripts/reports/free_body_truth.py in .venv-peers, the accuracy report's
truth). Asserted: as many flips; each flip's time within 1e-4 s of the truth's and the period within
1e-5 (the issue's goal: 1 %).
Usage: free_body_accuracy_test.py BUILD_DIR SOURCE_DIR"""
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
check = suite.check
seconds = 20.0
I, w0 = (1.0, 2.0, 3.0), (0.1, 5.0, 0.1)
truth = json.loads(subprocess.run(
    [suite.python, os.path.join(suite.source, "scripts", "reports", "free_body_truth.py"), "--inertia", *map(str, I),
     "--w0", *map(str, w0), "--seconds", str(seconds)], capture_output=True, text=True, check=True).stdout)
L = [i * w for i, w in zip(I, w0)]
norm = math.sqrt(sum(x * x for x in L))
Lhat = [x / norm for x in L]
with tempfile.TemporaryDirectory() as tmp:
    scene, table = os.path.join(tmp, "spin.yaml"), os.path.join(tmp, "spin.csv")
    with open(scene, "w") as f:
        f.write("gravity: [0, 0, 0]\nground: {height: -5}\n"
                "bodies: [{name: t, shape: box, size: [0.1, 0.1, 0.1], mass: 1, inertia: [1, 2, 3, 0, 0, 0], "
                "w: [0.1, 5, 0.1]}]\nsimulation: {integrator: linearly_implicit, dt: 0.001}\n")
    subprocess.run([os.path.join(suite.build, "tools", "igms-scenario"), "--scene", scene, "--seconds", str(seconds),
                    "--csv", table], check=True, capture_output=True)
    rows = list(csv.DictReader(open(table)))


def axis_y_along_L(r):  # the body's y axis (R's second column) on the momentum's direction
    w, x, y, z = (float(r["t." + k]) for k in ("qw", "qx", "qy", "qz"))
    col = (2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x))
    return sum(c * l for c, l in zip(col, Lhat))


flips = []
prev_t, prev = 0.0, axis_y_along_L({"t.qw": 1, "t.qx": 0, "t.qy": 0, "t.qz": 0})
for r in rows:
    t, now = float(r["t"]), axis_y_along_L(r)
    if prev > 0.0 >= now:
        flips.append(prev_t + (t - prev_t) * prev / (prev - now))
    prev_t, prev = t, now
print(f"igms flips at {[round(t, 6) for t in flips]} s; DOP853 at {[round(t, 6) for t in truth['flips']]} s")
check(len(flips) == len(truth["flips"]) and len(flips) >= 2, f"as many flips as the truth ({len(flips)})")
if len(flips) == len(truth["flips"]) and len(flips) >= 2:
    worst = max(abs(a - b) for a, b in zip(flips, truth["flips"]))
    check(worst < 1e-4, f"each flip within 1e-4 s of DOP853's ({worst:.2e} s)")
    period = (flips[-1] - flips[0]) / (len(flips) - 1)
    exact = (truth["flips"][-1] - truth["flips"][0]) / (len(flips) - 1)
    check(abs(period / exact - 1) < 1e-5, f"the period {period:.7f} s against {exact:.7f} s ({period / exact - 1:+.2e})")
suite.finish("free_body_accuracy_test")
