#!/usr/bin/env bash
# The project's Python environment (.venv, not committed): Debian's python3
# with its packages (numpy, matplotlib, yaml, pandas, pytest, tqdm, selenium) plus what
# exists only on PyPI, pinned: `lcm` (Debian has no LCM Python binding); nanobind and
# scikit-build-core (the igms module's build); ray and pyarrow (igms-sweep). numpy
# stays Debian's (a constraint), so matplotlib and the rest keep the numpy they were built for.
# Idempotent; prints the interpreter's path. Use it with the generated types:
#   PYTHONPATH=build/python:python $(scripts/setup/python_env.sh) my_script.py
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=.venv
pypi=(lcm==1.5.3 nanobind==3.1.0 scikit-build-core==1.1.2 ray==2.60.0 pyarrow==18.1.0)
modules="lcm numpy nanobind scikit_build_core ray pyarrow"
have_all() {
  "$venv/bin/python" -c "import importlib.util, sys; sys.exit(any(importlib.util.find_spec(m) is None for m in '$modules'.split()))" 2>/dev/null
}
if [[ ! -x $venv/bin/python ]] || ! have_all; then
  [[ -x $venv/bin/python ]] || /usr/bin/python3 -m venv --system-site-packages "$venv" >&2
  constraint=$(mktemp)
  trap 'rm -f "$constraint"' EXIT
  /usr/bin/python3 -c "import numpy; print('numpy==' + numpy.__version__)" >"$constraint"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -c "$constraint" "${pypi[@]}" >&2 ||
    { echo "python_env: could not install ${pypi[*]} from PyPI" >&2; exit 1; }
fi
echo "$PWD/$venv/bin/python"
