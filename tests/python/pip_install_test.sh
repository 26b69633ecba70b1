#!/usr/bin/env bash
# `pip install .` into a fresh virtual environment (no system packages): scikit-build-core and
# nanobind come from PyPI, CMake builds the module, and the installed package works away from the
# source tree: a scene steps, a kernel runs, igms-sweep answers. (Debian's C++ packages: scripts/setup/setup.sh.)
#   tests/python/pip_install_test.sh SOURCE_DIR
set -euo pipefail
src=$(cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 -m venv "$work/venv"
"$work/venv/bin/python" -m pip install --quiet --disable-pip-version-check "$src"
cd "$work"
"$work/venv/bin/python" - "$src" "$work" <<'PY'
import os
import sys

import numpy as np

import igms

src, work = sys.argv[1], sys.argv[2]
assert igms.__file__.startswith(os.path.join(work, "venv")), igms.__file__
sim = igms.Simulation(igms.Scene.load(os.path.join(src, "scenes", "box_slide.yaml")))
sim.step(400)
assert abs(sim.q[0] - 0.1019) < 5e-4, sim.q  # v0^2 / (2 mu g) = 101.9 mm
model = igms.Model.from_urdf(os.path.join(src, "models", "puma560.urdf"))
tau = model.rnea(np.zeros(6), np.zeros(6), np.zeros(6))
assert abs(tau[1] - 37.48366665) < 1e-6, tau
assert igms.robot_state_t.__name__ == "robot_state_t"  # the message types come with it
print("pip_install_test: igms installed from", src, "into", igms.__file__)
PY
"$work/venv/bin/igms-sweep" --help >/dev/null
echo "pip_install_test: ok"
