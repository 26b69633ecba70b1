#!/usr/bin/env python3
"""A dense pile of n^3 spheres as a scene: r 5 cm, 10 kg each, in n x n columns of n, each sphere resting
on the one below (touching), neighbouring columns 1 mm apart (inside igms's 5 mm contact margin, so every
neighbour is a candidate pair); the crowded scene of the contact benchmark (scripts/bench/bench.sh --contact).

  pile_scene.py N OUT.yaml"""
import sys


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    n, out = int(sys.argv[1]), sys.argv[2]
    lines = [f"# {n ** 3} spheres (r 5 cm, 10 kg) in {n} x {n} columns of {n}, touching vertically, 1 mm apart "
             "sideways (scripts/bench/pile_scene.py)", f"name: pile{n ** 3}", "ground: {height: 0}", "bodies:"]
    for i in range(n):
        for j in range(n):
            for k in range(n):
                lines.append(f"  - {{name: s{i}_{j}_{k}, shape: sphere, radius: 0.05, mass: 10, "
                             f"xyz: [{i * 0.101:.3f}, {j * 0.101:.3f}, {0.05 + 0.1 * k:.2f}]}}")
    lines.append("simulation: {integrator: linearly_implicit, dt: 0.001, rate_hz: 1000}")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
