#!/usr/bin/env bash
# The peers' environment for the peer benchmark (.venv-peers, not committed):
# PyPI `pin` (Pinocchio, whose wheel carries its C++ headers, CMake package and
# libraries under site-packages/cmeel.prefix) and `mujoco` (its C library and
# headers under site-packages/mujoco), pinned; and `scipy`, whose DOP853 gives
# the accuracy report its independent truth (scripts/reports/accuracy_peers.py); PyYAML, with which
# scripts/bench/contact_peers.py reads igms's scenes to build MuJoCo's. Kept apart from .venv: their
# numpy 2 would shadow Debian's numpy 1 that matplotlib was built for.
# Idempotent; prints the site-packages folder (CMake's IGMS_PEER_SITE).
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=.venv-peers
pin_version=4.1.0
mujoco_version=4.0.0
scipy_version=1.17.1
pyyaml_version=6.0.2
site() { "$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])'; }
if [[ ! -x $venv/bin/python ]] || [[ ! -d $(site 2>/dev/null)/cmeel.prefix/include/pinocchio ]] ||
   [[ ! -d $(site 2>/dev/null)/mujoco/include/mujoco ]] || [[ ! -d $(site 2>/dev/null)/scipy/integrate ]] ||
   [[ ! -d $(site 2>/dev/null)/yaml ]]; then
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv" >&2
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "pin==$pin_version" \
    "mujoco==$mujoco_version" "scipy==$scipy_version" "PyYAML==$pyyaml_version" >&2 ||
    { echo "peer_env: could not install pin $pin_version, mujoco $mujoco_version, scipy $scipy_version and PyYAML $pyyaml_version from PyPI" >&2
      exit 1; }
fi
site
