#!/usr/bin/env bash
# Every documented build option builds: configures and builds igms with the
# optional parts turned off (and -march=native on), each in a build folder of
# its own under out/, and runs the unit tests of the build without LCM. CI runs
# it after scripts/test.sh, so an option that does not build cannot land.
#   scripts/checks/check_build_options.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/setup/setup.sh >/dev/null  # the packages (and the main build)
configs=(
  "no-lcm-no-kdl:-DIGMS_WITH_LCM=OFF -DIGMS_WITH_KDL=OFF"
  "no-web-no-python-no-tests-no-bench-native:-DIGMS_WITH_WEB=OFF -DIGMS_WITH_PYTHON=OFF -DIGMS_BUILD_TESTS=OFF -DIGMS_BUILD_BENCH=OFF -DIGMS_NATIVE=ON"
)
mkdir -p out/build-options
for entry in "${configs[@]}"; do
  name=${entry%%:*}
  read -r -a flags <<<"${entry#*:}"
  dir=out/build-options/$name
  echo "== $name: ${flags[*]}"
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "${flags[@]}" >"$dir.configure.log" 2>&1 || {
    cat "$dir.configure.log"
    exit 1
  }
  grep -E "left out:" "$dir.configure.log" || true
  cmake --build "$dir" -j "$(nproc)" >"$dir.build.log" 2>&1 || {
    grep -E "error|FAILED" "$dir.build.log" | head -40
    echo "check_build_options: $name does not build (log: $dir.build.log)"
    exit 1
  }
done
(cd out/build-options/no-lcm-no-kdl && ctest -L unit --output-on-failure -j "$(nproc)")
echo "check_build_options: every documented option builds"
