#!/usr/bin/env bash
# igms as others use it: `cmake --install` into a temporary prefix, then a
# downstream CMake project (find_package(igms)) and a pkg-config build of the
# same program, both run on the PUMA; then the installed Python types read a
# committed log. Exits non-zero on any failure.
#   tests/package/install_test.sh BUILD_DIR
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "$1" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log"
for f in lib/cmake/igms/igmsConfig.cmake lib/pkgconfig/igms.pc include/igms/core/dynamics/rnea.h \
         include/igms/lcmtypes/igms/robot_state_t.hpp bin/igms-server bin/igms-viewer share/igms/web/page/index.html; do
  [[ -e $prefix/$f ]] || { echo "install_test: $f was not installed" >&2; exit 1; }
done
urdf=$src/models/puma560.urdf

# find_package(igms), away from the source tree.
cp -r "$src/tests/package/downstream" "$tmp/downstream"
cmake -S "$tmp/downstream" -B "$tmp/downstream/build" -DCMAKE_PREFIX_PATH="$prefix" >"$tmp/configure.log" ||
  { cat "$tmp/configure.log"; exit 1; }
cmake --build "$tmp/downstream/build" >"$tmp/build.log" || { cat "$tmp/build.log"; exit 1; }
cmake_out=$("$tmp/downstream/build/downstream" "$urdf")
echo "$cmake_out"

# pkg-config, the same program.
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
g++ -std=c++17 -O2 "$tmp/downstream/main.cc" -o "$tmp/downstream_pc" $(pkg-config --cflags --libs igms)
pc_out=$("$tmp/downstream_pc" "$urdf")
[[ "$pc_out" == "$cmake_out" ]] || { echo "install_test: pkg-config build differs: $pc_out" >&2; exit 1; }

# The PUMA at q = 0 holds its arm against gravity: joint 2 carries a torque, joint 1 (vertical axis) none.
python3 - "$cmake_out" <<'PY'
import sys
tau = [float(x) for x in sys.argv[1].splitlines()[0].split()[1:]]
assert len(tau) == 6, tau
assert abs(tau[0]) < 1e-9, tau
assert abs(tau[1]) > 1.0, tau
PY

# The installed Python types (lcm from the project's .venv) read a committed log.
python=$("$src/scripts/setup/python_env.sh")
pydir=$(find "$prefix/lib" -maxdepth 3 -type d -name dist-packages | head -1)
PYTHONPATH=$pydir "$python" - "$src/tests/replay/data/push.lcmlog" <<'PY'
import sys
import igmslog
log = igmslog.read(sys.argv[1])
assert log.info is not None and log.info.model_size > 0, "no session info"
assert log.states["q"].shape[1] == 6 and len(log.states["t"]) > 1000, log.states["q"].shape
assert not log.undecodable, log.undecodable
print("python: %d states, %d inputs, scene %s" % (len(log.states["t"]), len(log.inputs["seq"]), log.info.scene_path))
PY
echo "install_test: ok"
