#!/usr/bin/env bash
# Every committed log is readable by the stock tools and re-simulates from
# the log alone:
#  - Python's lcm.EventLog (PyPI lcm, .venv) reads as many events as igms does
#    (a .gz log after `zcat`, the documented one-liner);
#  - lcm-logplayer plays the push log to Debian's lcm-logger, which records
#    every event (private network namespace);
#  - a log copied to an empty folder elsewhere re-simulates bit for bit
#    (igms-replay resim) and on ODE (igms-ode-ref log), and its export holds
#    the model, with no repository;
#  - so does a new log of two robots (scenes/workcell.yaml, the PUMA and a
#    Go1): IGMS_SESSION_FILES carries both models and every mesh's hash.
#   tests/integration/log_portability_test.sh BUILD_DIR PORT SESSION_PORT
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "$1" && pwd)
port=$2
session_port=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python=$("$src/scripts/setup/python_env.sh")

for log in "$src"/tests/replay/data/*.lcmlog*; do
  name=$(basename "$log")
  plain=$log
  if [[ $log == *.gz ]]; then
    plain=$tmp/${name%.gz}
    zcat "$log" > "$plain"
  fi
  want=$("$build/tools/igms-replay" info "$log" | sed -n 's/.*: \([0-9]*\) events over.*/\1/p')
  got=$("$python" -c "import lcm, sys; print(sum(1 for _ in lcm.EventLog(sys.argv[1], 'r')))" "$plain")
  echo "$name: igms $want events, Python lcm.EventLog $got"
  [[ -n $want && $want == "$got" ]] || { echo "log_portability_test: $name: Python read $got of $want" >&2; exit 1; }
done

# lcm-logplayer -> lcm-logger, on a port of this test's own.
url="udpm://239.255.76.67:$port?ttl=0"
"$src/scripts/netns_run.sh" bash -c '
  lcm-logger -q -f --lcm-url="$1" "$2/replayed.lcmlog" & logger=$!
  sleep 0.5
  lcm-logplayer --lcm-url="$1" "$3" >/dev/null
  sleep 0.5
  kill -INT $logger; wait $logger || true' igms-logplay "$url" "$tmp" "$src/tests/replay/data/push.lcmlog"
want=$("$build/tools/igms-replay" info "$src/tests/replay/data/push.lcmlog" | sed -n 's/.*: \([0-9]*\) events over.*/\1/p')
got=$("$build/tools/igms-replay" info "$tmp/replayed.lcmlog" | sed -n 's/.*: \([0-9]*\) events over.*/\1/p')
echo "push.lcmlog through lcm-logplayer and lcm-logger: $got of $want events"
# UDP on loopback may drop a datagram or two under load; a format the player cannot read plays none.
(( got >= want * 99 / 100 )) || { echo "log_portability_test: lcm-logplayer played $got of $want" >&2; exit 1; }

# From the log alone, away from the repository.
mkdir "$tmp/elsewhere"
cp "$src/tests/replay/data/paper_push.lcmlog.gz" "$tmp/elsewhere/"
cd "$tmp/elsewhere"
"$build/tools/igms-replay" resim paper_push.lcmlog.gz --require-identical | tee "$tmp/resim.txt"
grep -q "model: the log's copy" "$tmp/resim.txt"
# An export carries the model too: the same bytes as the repository's.
"$build/tools/igms-replay" export paper_push.lcmlog.gz out >/dev/null
cmp out/puma560.urdf "$src/models/puma560.urdf" || fail_export=1
[[ -z ${fail_export:-} ]] || { echo "log_portability_test: the exported model differs" >&2; exit 1; }
grep -q "model_file: puma560.urdf" out/session.txt
if [[ -x $build/tools/igms-ode-ref ]]; then
  "$build/tools/igms-ode-ref" log paper_push.lcmlog.gz --json > "$tmp/ode.json"
  "$python" -c "import json,sys; j=json.load(open(sys.argv[1])); print('ODE replay from the log alone:', {k: j[k] for k in list(j)[:4]})" "$tmp/ode.json"
fi

# Two robots, recorded now (run_session.sh: lockstep server, the scripted hand, the logger).
(cd "$src" && IGMS_BUILD="$build" IGMS_SESSION_PORT=$session_port scripts/sessions/run_session.sh scenes/workcell.yaml \
   scenes/push_demo.yaml "$tmp/workcell" --seconds 2 >/dev/null)
mkdir "$tmp/elsewhere2"
cp "$tmp/workcell/session.lcmlog" "$tmp/elsewhere2/"
cd "$tmp/elsewhere2"
"$build/tools/igms-replay" resim session.lcmlog --require-identical | tee "$tmp/resim2.txt"
grep -q "models: the log's copies of 2 of the scene's 2 robots' models$" "$tmp/resim2.txt" ||
  { echo "log_portability_test: the two robots' log does not carry both models" >&2; exit 1; }
# Every mesh the Go1 names was hashed at record time (it is not here: "here missing").
meshes=$(grep -c "note: mesh package://example-robot-data/robots/go1_description/meshes/.*: recorded [0-9a-f]\{16\}, here missing" \
  "$tmp/resim2.txt" || true)
(( meshes >= 5 )) || { echo "log_portability_test: $meshes Go1 mesh hashes in the log" >&2; exit 1; }
"$build/tools/igms-replay" export session.lcmlog out >/dev/null
cmp out/go1_go1.urdf "$src/third_party/example-robot-data/robots/go1_description/urdf/go1.urdf"
cmp out/puma_puma560.urdf "$src/models/puma560.urdf"
PYTHONPATH="$build/python:$src/python" "$python" -c "
import sys, igmslog
log = igmslog.read(sys.argv[1])
texts = igmslog.model_texts(log)
assert sorted(texts) == ['go1', 'puma'] and all('<robot' in t for t in texts.values()), sorted(texts)
print('igmslog: the models of', ', '.join(sorted(texts)), 'from the log')" session.lcmlog
echo "log_portability_test: ok"
