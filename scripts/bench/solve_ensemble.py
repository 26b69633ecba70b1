#!/usr/bin/env python3
"""How many contact solves stop at the sweep limit, over an ensemble of nanometre moves.

One run's count is chaotic where boxes are knocked together (docs/environment.md: moving one box
by a few nm changes puma_table's count from 30 to 327), so a change to the solver is judged on the
sum over many runs. Each scene is run N times with its first free body moved k nm along x
(k = 0 .. N-1), with igms-scenario; per scene: the total, the median and the largest count, the
largest residual (m/s), the active-set solve's dense solves, the position corrections that stopped
at their sweep limit, the active-set islands that cycled (polish_cycles), the islands answered on the
linearised cone (exactly once seeded by it, or with the polytope's answer, and the largest angle, rad,
between a friction kept on the polytope and the one against its slip), and the deepest overlap of
any run and the median run's deepest (mm, igms-scenario's max_penetration).

  scripts/bench/solve_ensemble.py [--build build] [--runs 12] [--first 0]

Two ensembles of one build (--first 0 and --first 36, say) show how far a total moves by chance.
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
# scene, device script (or None), seconds
CASES = [("puma_table.yaml", None, 8), ("puma_table.yaml", "table_box_push.yaml", 6),
         ("table_clear.yaml", None, 8), ("workcell.yaml", None, 8)]
FIRST_BODY_X = re.compile(r"(bodies:\n(?:.*\n)*?.*?xyz: \[)([-0-9.e]+)")


def moved(text, nm):
    m = FIRST_BODY_X.search(text)
    if m is None:
        raise SystemExit("solve_ensemble: the scene has no free body to move")
    return text[:m.start(2)] + repr(float(m.group(2)) + 1e-9 * nm) + text[m.end(2):]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="the build directory (its tools/igms-scenario)")
    ap.add_argument("--runs", type=int, default=12, help="runs per scene (moves of first .. first+runs-1 nm)")
    ap.add_argument("--first", type=int, default=0,
                    help="the first run's move, nm (another ensemble of the same build: its spread)")
    args = ap.parse_args()
    scenario = os.path.join(os.path.abspath(args.build), "tools", "igms-scenario")
    # The variants sit beside scenes/ so that their relative model paths resolve as the originals'.
    work = tempfile.mkdtemp(prefix=".solve_ensemble_", dir=ROOT)
    try:
        print(f"{'scene':<18} {'device':<20} {'total':>6} {'median':>7} {'max':>5} {'worst residual':>15} {'dense solves':>13} "
              f"{'position':>9} {'cycles':>7} {'lin. exact':>10} {'polytope':>8} {'angle':>6} {'deepest mm':>11} {'median mm':>10}")
        for scene, device, seconds in CASES:
            text = open(os.path.join(ROOT, "scenes", scene)).read()
            counts, worst, rounds, position, cycles, deepest = [], 0.0, 0, 0, 0, []
            exact, polytope, angle = 0, 0, 0.0
            for k in range(args.first, args.first + args.runs):
                path = os.path.join(work, f"{k}_{scene}")
                with open(path, "w") as f:
                    f.write(moved(text, k))
                cmd = [scenario, "--scene", path, "--seconds", str(seconds)]
                if device:
                    cmd += ["--device", "scripted:" + os.path.join(ROOT, "scenes", device)]
                result = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
                solve = result["contact_solve"]
                deepest.append(1e3 * result["max_penetration"])
                cycles += solve["polish_cycles"]
                exact += solve["linearised_exact"]
                polytope += solve["linearised"]
                angle = max(angle, solve["max_linearised_angle"])
                counts.append(solve["unconverged"])
                worst = max(worst, solve["max_residual"])
                rounds += solve["polish_rounds"]
                position += solve["position_unconverged"]
            print(f"{scene:<18} {device or '-':<20} {sum(counts):>6} {statistics.median(counts):>7g} {max(counts):>5} "
                  f"{worst:>15.1e} {rounds:>13} {position:>9} {cycles:>7} {exact:>10} {polytope:>8} {angle:>6.3f} {max(deepest):>11.3f} {statistics.median(deepest):>10.3f}")
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
