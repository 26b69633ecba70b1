#!/usr/bin/python3
"""igms against Pinocchio and MuJoCo, side by side: for each robot, `igms-dyn bench --json` and
`igms-peer-bench` (Pinocchio and MuJoCo on the same URDF, the same kernels and sampling) run in turn,
round after round (interleaved processes, so a noisy stretch hits every library alike). Each cell is
the median over the rounds of each process's own median; the ratio is igms / the best peer (below
1.0 igms is faster). igms's forward dynamics is the faster of its two paths (LDLt through H, ABA).
    scripts/bench/peer_table.py BUILD_DIR PEER_BUILD_DIR [--rounds N] [--robots a,b] [--json FILE]"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

KERNELS = ("rnea", "crba", "fd", "fk", "jacobian", "step")
HEADS = {"rnea": "RNEA", "crba": "CRBA (H)", "fd": "FD", "fk": "FK all", "jacobian": "FK + J", "step": "1 ms step"}


def robots(src, tmp, peer_bin):
    erd = os.path.join(src, "third_party/example-robot-data/robots")
    chains = {}
    for n in (30, 100):
        chains[n] = os.path.join(tmp, f"chain{n}.urdf")
        subprocess.run([peer_bin, "--write-chain", str(n), chains[n]], check=True)
    talos = os.path.join(erd, "talos_data/robots/talos_reduced.urdf")
    return [("UR5", os.path.join(erd, "ur_description/urdf/ur5_robot.urdf"), False),
            ("Panda", os.path.join(erd, "panda_description/urdf/panda.urdf"), False),
            ("PUMA 560", os.path.join(src, "models/puma560.urdf"), False),
            ("chain 30", chains[30], False),
            ("chain 100", chains[100], False),
            ("Talos floating", talos, True),
            ("Talos fixed", talos, False)]


def neutral_trace(dyn, path, floating, nq, nv):
    """The trace of igms's H at the neutral configuration (zeros; a floating base's quaternion at identity)."""
    q = [0.0] * nq
    if floating:
        q[3] = 1.0  # igms: x y z qw qx qy qz
    line = json.dumps({"q": q, "v": [0.0] * nv})
    cmd = [dyn] + (["--floating-base"] if floating else []) + ["eval", "--model", path]
    out = subprocess.run(cmd, input=line + "\n", check=True, capture_output=True, text=True).stdout
    M = json.loads(out.strip().splitlines()[0])["M"]
    return sum(M[i][i] for i in range(len(M)))


def run_json(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build")
    ap.add_argument("peer_build")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--robots", default="", help="only these (comma-separated, as in the table)")
    ap.add_argument("--json", default="")
    a = ap.parse_args()
    src = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    dyn = os.path.join(a.build, "tools/igms-dyn")
    peer = os.path.join(a.peer_build, "bench/igms-peer-bench")
    with tempfile.TemporaryDirectory() as tmp:
        todo = [r for r in robots(src, tmp, peer) if not a.robots or r[0] in a.robots.split(",")]
        samples = {}  # (robot, lib, kernel) -> [us per round]
        info, checks = {}, {}
        for rnd in range(a.rounds):
            for name, path, floating in todo:
                flag = ["--floating-base"] if floating else []
                ours = run_json([dyn] + flag + ["bench", "--model", path, "--json"])
                ours["fd_us"] = min(ours["fd_us"], ours["aba_us"])  # igms's faster forward dynamics
                theirs = run_json([peer, "--model", path, "--frame", ours["jacobian_frame"]] + flag)
                info[name] = (theirs["nv"], theirs["versions"])
                if rnd == 0:
                    checks[name] = (neutral_trace(dyn, path, floating, theirs["nq"], theirs["nv"]),
                                    theirs["trace_H_neutral"], ours["jacobian_frame"], theirs["jacobian_frame"])
                for k in KERNELS:
                    samples.setdefault((name, "igms", k), []).append(ours[k + "_us"])
                    samples.setdefault((name, "pinocchio", k), []).append(theirs["pinocchio"][k + "_us"])
                    samples.setdefault((name, "mujoco", k), []).append(theirs["mujoco"][k + "_us"])
            print(f"round {rnd + 1} of {a.rounds} done", file=sys.stderr)
    med = {key: statistics.median(v) for key, v in samples.items()}
    versions = next(iter(info.values()))[1] if info else {}
    load = os.getloadavg()
    print(f"igms vs Pinocchio {versions.get('pinocchio')} (-O3) and MuJoCo {versions.get('mujoco')}: "
          f"median of {a.rounds} interleaved rounds, us per call; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    print()
    print("| robot (nv) | " + " | ".join(HEADS[k] for k in KERNELS) + " |")
    print("|---|" + "---:|" * len(KERNELS))
    rows, behind = [], 0
    for name, _, _ in todo:
        cells = []
        for k in KERNELS:
            ours, pin, mj = (med[(name, lib, k)] for lib in ("igms", "pinocchio", "mujoco"))
            ratio = ours / min(pin, mj)
            behind += ratio > 1.0
            cells.append(f"{ratio:.2f}")
            rows.append({"robot": name, "kernel": k, "igms_us": ours, "pinocchio_us": pin, "mujoco_us": mj,
                         "ratio": ratio})
        print(f"| {name} ({info[name][0]}) | " + " | ".join(cells) + " |")
    print()
    print("ratio = igms / best peer; the microseconds:")
    for r in rows:
        print(f"  {r['robot']:15s} {r['kernel']:9s} igms {r['igms_us']:8.3f}  Pinocchio {r['pinocchio_us']:8.3f}  "
              f"MuJoCo {r['mujoco_us']:8.3f}  ratio {r['ratio']:.2f}")
    print(f"cells above 1.0: {behind} of {len(rows)}")
    print()
    print("the same robots? trace of H at the neutral configuration (independent of joint order), and the Jacobian's frame:")
    for name, (ours, theirs, frame, their_frames) in checks.items():
        print(f"  {name:15s} igms {ours:.6g}  Pinocchio {theirs['pinocchio']:.6g}  MuJoCo {theirs['mujoco']:.6g}  "
              f"(relative {abs(theirs['pinocchio'] - ours) / ours:.1e}, {abs(theirs['mujoco'] - ours) / ours:.1e});  "
              f"frame igms {frame}, Pinocchio {their_frames['pinocchio']}, MuJoCo body {their_frames['mujoco']}")
    if a.json:
        json.dump({"rounds": a.rounds, "load": load, "versions": versions, "rows": rows}, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
