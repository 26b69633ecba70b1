#!/usr/bin/env bash
# Fresh-machine set-up: installs the Debian packages igms needs (as root,
# idempotent, quiet when all are there), then configures and builds (Release).
#   scripts/setup.sh [extra cmake -D options]
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake ninja-build g++ pkg-config            # toolchain
  libeigen3-dev                               # dynamics core
  liburdfdom-dev libyaml-cpp-dev              # model loaders (URDF, DH tables, scenes)
  libassimp-dev                               # meshes (STL, Collada, OBJ) for collision and visuals
  liblcm-dev liblcm-bin liblcm-java           # bus: C++ library, lcm-gen, lcm-logplayer, lcm-spy (lcm.jar)
  libfcl-dev libode-dev                       # collision (FCL) and the ODE reference simulator
  liborocos-kdl-dev                           # KDL: cross-checks and benchmark peer
  libcli11-dev                                # command lines (CLI11)
  libgtest-dev nlohmann-json3-dev zlib1g-dev  # tests, JSON output, compressed logs
  libjchart2d-java                            # lcm-spy's charts (scripts/lcm_spy.sh; NoClassDefFoundError without)
  iproute2 util-linux                         # ip, unshare: private network namespace for LCM
  python3 python3-yaml python3-matplotlib     # model generators, plots
  python3-pip python3-venv python3-numpy      # PyPI: example-robot-data (fetch_robots.sh), lcm (python_env.sh)
  libwebsocketpp-dev libboost-dev libjs-three # browser view: HTTP/WebSocket server, three.js in the page
  chromium chromium-driver python3-selenium   # browser tests, demo screenshots (headless Chromium)
  fonts-dejavu-core socat                     # the page's text; scripts/live.sh's bridge out of the netns
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Real robot models (Panda, UR5, ...) for the mesh tests and scenes; without PyPI those tests skip.
scripts/fetch_robots.sh || echo "setup: example-robot-data not fetched; the tests that need it will skip" >&2
# Python's LCM binding (PyPI only) in .venv: igmslog.py and the Python tests.
scripts/python_env.sh >/dev/null || echo "setup: .venv without lcm; the Python log tests will fail" >&2
# Pinocchio, MuJoCo and SciPy (PyPI only) in .venv-peers: the accuracy report's independent truth and
# MuJoCo's integrators (independent_truth_test), and the optional peer benchmark.
scripts/peer_env.sh >/dev/null || echo "setup: no .venv-peers; independent_truth_test will fail" >&2

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >build.configure.log 2>&1 || {
  cat build.configure.log
  exit 1
}
grep -E "built:|left out:" build.configure.log || true
cmake --build build -j "$(nproc)"
