#!/usr/bin/env bash
# The project's Python environment (.venv, not committed): Debian's python3
# with its packages (numpy, matplotlib, yaml, selenium) plus what exists only
# on PyPI: `lcm` (Debian has no LCM Python binding). Idempotent; prints the
# interpreter's path. Use it with the generated types:
#   PYTHONPATH=build/python:python $(scripts/python_env.sh) my_script.py
set -euo pipefail
cd "$(dirname "$0")/.."
venv=.venv
lcm_version=1.5.3
if [[ ! -x $venv/bin/python ]] || ! $venv/bin/python -c "import lcm, numpy" 2>/dev/null; then
  rm -rf "$venv"
  /usr/bin/python3 -m venv --system-site-packages "$venv" >&2
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "lcm==$lcm_version" >&2 ||
    { echo "python_env: could not install lcm $lcm_version from PyPI" >&2; exit 1; }
fi
echo "$PWD/$venv/bin/python"
