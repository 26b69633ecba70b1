#!/usr/bin/env bash
# Benchmarks: igms vs KDL in one run (medians and ratios), then igms-dyn bench
# per model. Results also go to out/bench/.
#   scripts/bench/bench.sh [igms-bench options]
#   scripts/bench/bench.sh --peers [--rounds N] [--robots a,b]   igms vs Pinocchio and MuJoCo (PyPI pin and
#       mujoco in .venv-peers, igms-peer-bench built in build-peers/), interleaved rounds, ratios
#   scripts/bench/bench.sh --contact [--rounds N] [--steps N]    igms's step vs MuJoCo's mj_step on the contact scenes
#       and dense piles of 27 to 1000 spheres (scripts/bench/pile_scene.py), the same models as MJCF from
#       scripts/bench/contact_peers.py, interleaved, medians and ratios, how far each engine's free bodies went
#       -> out/bench/contact*.json
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/setup/setup.sh >/dev/null
mkdir -p out/bench
# build-peers/: igms built against the peers' libraries from .venv-peers (Pinocchio, MuJoCo).
configure_peers() {
  local site
  site=$(scripts/setup/peer_env.sh)
  cmake -S . -B build-peers -G Ninja -DCMAKE_BUILD_TYPE=Release -DIGMS_PEER_BENCH=ON -DIGMS_PEER_SITE="$site" \
    -DIGMS_BUILD_TESTS=OFF -DIGMS_WITH_WEB=OFF >out/bench/peers.configure.log 2>&1 ||
    { echo "bench.sh: configuring the peer benchmark failed (out/bench/peers.configure.log)" >&2; exit 1; }
}
if [[ ${1:-} == --peers ]]; then
  shift
  configure_peers
  cmake --build build-peers --target igms-peer-bench >/dev/null
  /usr/bin/python3 scripts/bench/peer_table.py build build-peers --json out/bench/peers.json "$@" | tee out/bench/peers.txt
  exit "${PIPESTATUS[0]}"
fi
if [[ ${1:-} == --contact ]]; then
  shift
  configure_peers
  cmake --build build-peers --target igms-contact-bench igms-dyn >/dev/null
  scenes=(go1_stand talos_stand box_slope box_slide box_tower box_pyramid sphere_pile ball_lattice)
  args=()
  for s in "${scenes[@]}"; do args+=(--scene "scenes/$s.yaml"); done
  # Dense piles of 27, 216, 512 and 1000 spheres (columns 1 mm apart: every neighbour inside the margin).
  mkdir -p out/bench/scenes
  for n in 3 6 8 10; do
    /usr/bin/python3 scripts/bench/pile_scene.py $n out/bench/scenes/pile$((n * n * n)).yaml
    args+=(--scene out/bench/scenes/pile$((n * n * n)).yaml)
  done
  .venv-peers/bin/python scripts/bench/contact_peers.py "${args[@]}" --out out/bench/mjcf
  build-peers/bench/igms-contact-bench --mjcf-dir out/bench/mjcf "${args[@]}" --json out/bench/contact.json "$@" |
    tee out/bench/contact.txt
  [[ ${PIPESTATUS[0]} == 0 ]] || exit 1
  # MuJoCo's lattice comes apart from about 2.5 s (its balls roll metres away), so the row above times
  # igms's standing lattice against MuJoCo's scattered heap: its first second, where both stand, too.
  echo "ball_lattice over its first second (no warm-up), where both engines' lattices stand:" | tee -a out/bench/contact.txt
  build-peers/bench/igms-contact-bench --mjcf-dir out/bench/mjcf --scene scenes/ball_lattice.yaml --warm 0 --rounds 5 \
    --steps 200 --json out/bench/contact_lattice_standing.json | tee -a out/bench/contact.txt
  exit "${PIPESTATUS[0]}"
fi
build/bench/igms-bench --json out/bench/igms_vs_kdl.json "$@" | tee out/bench/igms_vs_kdl.txt
for m in puma560.urdf arm7.urdf; do build/tools/igms-dyn bench --model models/$m; done | tee out/bench/igms_dyn.txt
build/tools/igms-dyn bench --model models/quadruped.urdf --floating-base | tee -a out/bench/igms_dyn.txt
