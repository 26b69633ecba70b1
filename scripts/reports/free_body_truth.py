#!/usr/bin/env python3
"""The free rigid body's truth for the accuracy checks: Euler's equations, I w' = -w x I w, with the
orientation's kinematics R' = R [w]x, integrated by SciPy's DOP853 at rtol = atol = 1e-12 (the
accuracy report's truth), from a body at rest in space with inertia I (principal, body axes) and
angular velocity w0 (body axes, R = identity at t = 0). Prints JSON: the times at which the body's
intermediate axis (y) turns through the plane normal to the angular momentum, downward (the
Dzhanibekov flips), and the energy at the end.

Runs in .venv-peers (scipy).
  free_body_truth.py --inertia 1 2 3 --w0 0.1 5 0.1 --seconds 20"""
import argparse
import json

import numpy as np
from scipy.integrate import solve_ivp


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--inertia", type=float, nargs=3, required=True)
    p.add_argument("--w0", type=float, nargs=3, required=True)
    p.add_argument("--seconds", type=float, required=True)
    a = p.parse_args()
    I = np.array(a.inertia)
    L = I * np.array(a.w0)  # world angular momentum (R = 1 at the start): constant
    Lhat = L / np.linalg.norm(L)

    def rate(t, y):
        w, R = y[:3], y[3:].reshape(3, 3)
        dw = -np.cross(w, I * w) / I
        W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        return np.concatenate([dw, (R @ W).ravel()])

    def crossing(t, y):  # the body's y axis against the momentum's direction
        return y[3:].reshape(3, 3)[:, 1] @ Lhat

    crossing.direction = -1
    y0 = np.concatenate([a.w0, np.eye(3).ravel()])
    sol = solve_ivp(rate, (0.0, a.seconds), y0, method="DOP853", rtol=1e-12, atol=1e-12, events=crossing)
    w = sol.y[:3, -1]
    print(json.dumps({"flips": [float(t) for t in sol.t_events[0]], "energy": float(0.5 * np.sum(I * w * w)),
                      "energy0": float(0.5 * np.sum(I * np.array(a.w0) ** 2))}))


if __name__ == "__main__":
    main()
