#!/usr/bin/python3
"""scripts/bench/solve_ensemble.py, as a person runs it: with one run per scene (a move of 0 nm) each
row is the shipped scene's own run, so its count and residual are igms-scenario's on the scene itself;
with two, the 1 nm move is a different run (the count is chaotic, docs/environment.md) and the total
is the sum of both.
  solve_ensemble_test.py BUILD_DIR"""
import json
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCRIPT = os.path.join(ROOT, "scripts", "bench", "solve_ensemble.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
from solve_ensemble import CASES  # noqa: E402  (the scenes, devices and durations the script runs)


def rows(build, runs, first=0):
    out = subprocess.run([sys.executable, SCRIPT, "--build", build, "--runs", str(runs), "--first", str(first)], check=True,
                         capture_output=True, text=True).stdout.splitlines()
    assert out[0].split()[:2] == ["scene", "device"], out[0]
    return [line.split() for line in out[1:]]


def main():
    build = os.path.abspath(sys.argv[1])
    scenario = os.path.join(build, "tools", "igms-scenario")
    failures = []
    one = rows(build, 1)
    if len(one) != len(CASES):
        failures.append(f"{len(CASES)} scenes, not {len(one)}")
    for (scene, device, total, median, largest, worst, dense, position, cycles, exact, polytope, angle, deepest,
         median_deepest), (_, script, seconds) in zip(one, CASES):
        cmd = [scenario, "--scene", os.path.join(ROOT, "scenes", scene), "--seconds", str(seconds)]
        if script:
            cmd += ["--device", "scripted:" + os.path.join(ROOT, "scenes", script)]
        result = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
        solve, depth = result["contact_solve"], 1e3 * result["max_penetration"]
        same = (int(total) == solve["unconverged"] == int(largest) and float(median) == solve["unconverged"]
                and int(dense) == solve["polish_rounds"] and int(position) == solve["position_unconverged"]
                and abs(float(worst) - solve["max_residual"]) <= 0.06 * solve["max_residual"]
                and int(cycles) == solve["polish_cycles"]
                and int(exact) == solve["linearised_exact"] and int(polytope) == solve["linearised"]
                and abs(float(angle) - solve["max_linearised_angle"]) <= 5e-4
                and abs(float(deepest) - depth) <= 5e-4 and float(deepest) == float(median_deepest))
        print(f"{'ok  ' if same else 'FAIL'} {scene} {device}: {total} unconverged, {dense} dense solves, {position} "
              f"position corrections unconverged, {cycles} cycles, {exact} / {polytope} islands on the linearised cone "
              f"({angle} rad), {deepest} mm deepest (igms-scenario on the scene: "
              f"{solve['unconverged']}, {solve['polish_rounds']}, {solve['position_unconverged']}, {solve['polish_cycles']}, "
              f"{solve['linearised_exact']} / {solve['linearised']} ({solve['max_linearised_angle']:.3f}), {depth:.4f} mm)")
        if not same:
            failures.append(f"{scene} {device}")
    two = rows(build, 2)
    for (scene, device, total, *_), (_, _, total1, *_) in zip(two, one):
        if int(total) < int(total1):
            failures.append(f"{scene} {device}: two runs' total {total} below the first run's {total1}")
    # --first: the second run alone (moved 1 nm) is what the two runs add to the first
    second = rows(build, 1, first=1)
    differs = False
    for (scene, device, total, *_), first_row, second_row in zip(two, one, second):
        total1, total2 = first_row[2], second_row[2]
        # any figure (counts, residual, dense solves, corrections): the unconverged counts alone are all
        # 0 once the solve converges everywhere, and the check would then fail for the wrong reason
        differs = differs or second_row[2:] != first_row[2:]
        if int(total) != int(total1) + int(total2):
            failures.append(f"{scene} {device}: --first 1 gave {total2}, not the two runs' {total} less {total1}")
    print(f"{'ok  ' if differs else 'FAIL'} --first 1 runs another ensemble: a figure differs from --first 0's")
    if not differs:
        failures.append("--first 1 gave every figure --first 0 gave (the move ignored?)")
    if failures:
        print("FAILED: " + "; ".join(failures), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
