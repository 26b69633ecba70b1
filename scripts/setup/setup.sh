#!/usr/bin/env bash
# Fresh-machine set-up: installs the Debian packages igms needs (as root,
# idempotent, quiet when all are there), then configures and builds (Release).
#   scripts/setup/setup.sh [extra cmake -D options]
# Its stages and the build's progress go to stderr (callers that silence stdout still show them);
# the build's full output is in build.log, and its tail is printed when it fails.
set -euo pipefail
cd "$(dirname "$0")/../.."
stage() { echo "setup: $*" >&2; }

packages=(
  cmake ninja-build g++ pkg-config            # toolchain
  libeigen3-dev                               # dynamics core
  liburdfdom-dev libyaml-cpp-dev              # model loaders (URDF, DH tables, scenes)
  libassimp-dev                               # meshes (STL, Collada, OBJ) for collision and visuals
  liblcm-dev liblcm-bin liblcm-java           # bus: C++ library, lcm-gen, lcm-logplayer, lcm-spy (lcm.jar)
  libssl-dev                                  # the signed bus: AES-256-GMAC, HMAC-SHA256 (OpenSSL)
  libfcl-dev libode-dev                       # collision (FCL) and the ODE reference simulator
  liborocos-kdl-dev                           # KDL: cross-checks and benchmark peer
  libcli11-dev                                # command lines (CLI11)
  libgtest-dev nlohmann-json3-dev zlib1g-dev  # tests, JSON output, compressed logs
  libjchart2d-java                            # lcm-spy's charts (scripts/sessions/lcm_spy.sh; NoClassDefFoundError without)
  iproute2 util-linux                         # ip, unshare: private network namespace for LCM
  python3 python3-yaml python3-matplotlib     # model generators, plots
  python3-cryptography                        # Python on a signed bus (python/igmsbus.py: a device in Python)
  python3-pip python3-venv python3-numpy      # PyPI: example-robot-data (fetch_robots.sh), lcm (python_env.sh)
  python3-dev python3-pytest                  # the igms Python module (nanobind, from PyPI) and its tests
  python3-pandas python3-tqdm                 # igms-sweep: its results as a table, its progress bar
  libwebsocketpp-dev libboost-dev libjs-three # browser view: HTTP/WebSocket server, three.js in the page
  chromium chromium-driver python3-selenium   # browser tests, demo screenshots (headless Chromium)
  fonts-dejavu-core socat                     # the page's text; scripts/live.sh's bridge out of the netns
)
stage "[1/6] Debian packages"
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${#missing[@]} packages (a few minutes on a fresh machine): ${missing[*]}" >&2
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Real robot models (Panda, UR5, ...) for the mesh tests and scenes; without PyPI those tests skip.
stage "[2/6] robot models (example-robot-data)"
scripts/setup/fetch_robots.sh || echo "setup: example-robot-data not fetched; the tests that need it will skip" >&2
# What exists only on PyPI in .venv: LCM's binding (igmslog.py, the Python tests), nanobind and
# scikit-build-core (the igms module, configured below with .venv's interpreter), Ray and pyarrow (igms-sweep).
stage "[3/6] Python environments (.venv, .venv-peers)"
scripts/setup/python_env.sh >/dev/null || echo "setup: .venv without lcm, nanobind or ray; the Python tests will fail" >&2
# Pinocchio, MuJoCo and SciPy (PyPI only) in .venv-peers: the accuracy report's independent truth and
# MuJoCo's integrators (independent_truth_test), and the optional peer benchmark.
scripts/setup/peer_env.sh >/dev/null || echo "setup: no .venv-peers; independent_truth_test will fail" >&2

stage "[4/6] configure (build.configure.log)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >build.configure.log 2>&1 || {
  cat build.configure.log
  exit 1
}
grep -E "built:|left out:" build.configure.log || true
# Ninja's "[k/N]" lines, one progress line per tenth on stderr; everything in build.log.
stage "[5/6] build (build.log)"
set +e
cmake --build build -j "$(nproc)" 2>&1 | tee build.log | awk '
  match($0, /^\[[0-9]+\/[0-9]+\]/) {
    split(substr($0, 2, RLENGTH - 2), kn, "/")
    pct = int(100 * kn[1] / kn[2])
    if (pct >= shown + 10 || kn[1] == kn[2]) { printf "setup: build %d%% (%d of %d steps)\n", pct, kn[1], kn[2] > "/dev/stderr"; shown = pct }
  }'
status=${PIPESTATUS[0]}
set -e
if ((status != 0)); then
  echo "setup: the build failed; the end of build.log:" >&2
  tail -n 40 build.log >&2
  exit "$status"
fi
# The module the build made (build/python/igms) importable from .venv, as an editable install would make it,
# and igms-sweep on .venv's PATH. `pip install .` builds and installs it anywhere else (docs/python.md).
stage "[6/6] the igms module into .venv"
if [[ -f build/python/igms/__init__.py ]] && ls build/python/igms/_igms*.so >/dev/null 2>&1; then
  site=$(.venv/bin/python -c "import sysconfig; print(sysconfig.get_paths()['purelib'])")
  echo "$PWD/build/python" >"$site/igms_build_tree.pth"
  printf '#!/bin/sh\n# igms-sweep from the build tree (scripts/setup/setup.sh)\nexec "%s" -m igms.sweep_cli "$@"\n' \
    "$PWD/.venv/bin/python" >.venv/bin/igms-sweep
  chmod +x .venv/bin/igms-sweep
else
  echo "setup: the igms module was not built (see build.configure.log); .venv has no igms" >&2
fi
stage "done"
