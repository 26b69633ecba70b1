#!/usr/bin/env python3
"""A dense pile of n^3 spheres as a scene: r 5 cm, 10 kg each, in n x n columns of n, each sphere resting
on the one below (touching), neighbouring columns GAP mm apart (default 1: inside igms's 5 mm contact
margin, so every neighbour is a candidate pair); the crowded scene of the contact benchmark
(scripts/bench/bench.sh --contact). With --gap 0 every sphere touches its neighbours on all sides: one
island of contacts (scenes/ball_lattice.yaml is n 6, --gap 0, --name ball_lattice).

  pile_scene.py N OUT.yaml [--gap MM] [--name NAME]"""
import argparse


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n", type=int, help="spheres along each side")
    parser.add_argument("out", help="the scene file to write")
    parser.add_argument("--gap", type=float, default=1.0, help="mm between neighbouring columns")
    parser.add_argument("--name", help="the scene's name (default pile<n^3>)")
    a = parser.parse_args()
    n, pitch = a.n, 0.1 + a.gap / 1000
    name = a.name or f"pile{n ** 3}"
    side = "touching" if a.gap == 0 else f"{a.gap:g} mm apart"
    lines = [f"# {n ** 3} spheres (r 5 cm, 10 kg) in {n} x {n} columns of {n}, touching vertically, {side} "
             f"sideways (scripts/bench/pile_scene.py {n} OUT --gap {a.gap:g})", f"name: {name}", "ground: {height: 0}",
             "bodies:"]
    for i in range(n):
        for j in range(n):
            for k in range(n):
                lines.append(f"  - {{name: s{i}_{j}_{k}, shape: sphere, radius: 0.05, mass: 10, "
                             f"xyz: [{i * pitch:.4f}, {j * pitch:.4f}, {0.05 + 0.1 * k:.2f}]}}")
    lines.append("simulation: {integrator: linearly_implicit, dt: 0.001, rate_hz: 1000}")
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
