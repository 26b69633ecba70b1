#!/usr/bin/env bash
# A device on the bus, from Python (examples/python_device.py): it publishes
# device_reading_t at 500 Hz and renders the device_force_t the client sends
# back, on a signed bus, playing the paper's push (the targets
# examples/device_plugin/paper_push.targets, the scripted device's hand).
# The server steps in lockstep. Asserts: the paper's two pushes reach the arm,
# the client holds 1 kHz and the device its own rate, no genuine message is
# refused either way; bad readings sent beside it (NaN, out of range, out of
# order, undecodable, signed by a second key holder: refused as other_sender,
# the client being pinned to its device; unsigned; another key) are refused
# and counted by reason and change nothing; when the device stops, the client says so and
# ramps the force out. Prints the latency the bus adds (reading -> the cycle
# that used it, and the force's way back), p50 and p99.
#   tests/integration/lcm_device_test.sh BUILD_DIR PORT
set -euo pipefail
build=$(cd "${1:?build dir}" && pwd)
port=${2:?port}
cd "$(dirname "$0")/../.."
source scripts/lib/session.sh
igms_in_netns "$0" "$@"
export IGMS_BUILD=$build
igms_build=$build
work=$(mktemp -d /tmp/igms-lcmdev.XXXXXX)
trap 'igms_stop_all; igms_drop_key; rm -rf "$work"' EXIT
url="udpm://239.255.76.67:$port?ttl=0"
scene=scenes/puma_obstacle.yaml
python=$(scripts/setup/python_env.sh)
export PYTHONPATH="$PWD/python:$build/python"
igms_use_key

run() {  # OUT_DIR with_bad_readings [quiet: no logger, for the latency alone]
  local out=$1 bad=$2 quiet=${3:-0}
  mkdir -p "$out"
  [[ $quiet == 1 ]] || igms_start_logger "$out/session.lcmlog" "$url" -q --wait-session-s 5 \
    -c 'IGMS_(SESSION_INFO|HAPTIC_INPUT|ROBOT_STATE|SERVER_STATUS|CLIENT_STATUS|DEVICE_STATUS)'
  igms_start_server "$scene" "$url" --clock lockstep --quiet 2> "$out/server.log"
  "$python" examples/python_device.py --targets examples/device_plugin/paper_push.targets --lcm-url "$url" \
    --duration 4 --stats "$out/device.json" ${device_options:-} 2> "$out/device.log" &
  igms_pids+=($!)
  if [[ $bad == 1 ]]; then
    "$python" tests/support/bad_device_readings.py "$url" "$IGMS_KEY_FILE" 4 "$out/bad.json" &
    igms_pids+=($!)
  fi
  igms_run_client "$scene" lcm "$url" --duration 5 --connect-timeout 30 2> "$out/client.log"
  sleep 0.5
  igms_stop_all
  [[ $quiet == 0 ]] || return 0
  "$build/tools/igms-replay" export "$out/session.lcmlog" "$out/export" 2>/dev/null
  /usr/bin/python3 scripts/reports/session_summary.py "$out" "$(basename "$out")" > /dev/null
}

device_options="--max-stiffness 800" run "$work/quiet" 0 1  # an Omni's: the coupling is felt scaled
run "$work/alone" 0
run "$work/bad" 1
"$python" - "$work" <<'PY'
import json, os, re, sys
import igmslog
work = sys.argv[1]
fails = 0
def check(ok, what, detail=""):
    global fails
    print(("ok    " if ok else "FAIL  ") + what + (": " + detail if detail else ""))
    fails += 0 if ok else 1

def latency(run):
    dev = json.load(open(os.path.join(work, run, "device.json")))
    print("      %s: reading -> force p50 %.0f us, p99 %.0f us; the bus adds p50 %.0f us, p99 %.0f us "
          "(the reading's age at the cycle p50 %.0f, p99 %.0f; the force's way back p50 %.0f, p99 %.0f)" %
          (run, dev["latency_us_p50"], dev["latency_us_p99"], dev["added_us_p50"], dev["added_us_p99"],
           dev["reading_age_us_p50"], dev["reading_age_us_p99"], dev["force_way_us_p50"], dev["force_way_us_p99"]))
    return dev

# The latency with nothing else on the machine (no logger): the figure the issue asks for.
dev = latency("quiet")
# The median is the path's own (a reading waits half a servo period for its cycle); the p99 is this VM's
# scheduling on 2 cores (stalls of 2-4 ms, ../TRAPS), so it is held loosely and the goal printed.
check(dev["added_us_p50"] <= 1500, "quiet: the bus adds under 1.5 ms at p50", "%.0f us" % dev["added_us_p50"])
check(dev["added_us_p99"] <= 10000, "quiet: the bus adds under 10 ms at p99 (the goal, 2 ms: %s)" %
      ("yes" if dev["added_us_p99"] <= 2000 else "NO"), "%.0f us" % dev["added_us_p99"])
check(dev["rate_hz"] >= 250, "quiet: the Python device at its own rate", "%.1f Hz" % dev["rate_hz"])
quiet_log = open(os.path.join(work, "quiet", "client.log")).read()
check("coupling: the scene's springs are 8000 N/m at the device (k x workspace scale 4), over its stable 800 N/m: "
      "the hand feels 0.1 of the force" in quiet_log, "quiet: a device of 800 N/m feels the coupling scaled to it",
      next((l for l in quiet_log.splitlines() if "coupling" in l), "no coupling line"))

for run in ("alone", "bad"):
    d = os.path.join(work, run)
    s = json.load(open(os.path.join(d, "summary.json")))
    dev = json.load(open(os.path.join(d, "device.json")))
    log = open(os.path.join(d, "client.log")).read()
    pushes = [e for e in s["interactions"] if e["mode"] == "push" and e["max_force_N"] > 1.0]
    check(len(pushes) >= 2, run + ": the paper's two pushes reach the arm",
          ", ".join("%.3f-%.3f s %.2f N" % (e["start_s"], e["end_s"], e["max_force_N"]) for e in pushes))
    check(s["client_rate_hz"] >= 990, run + ": the client holds 1 kHz", "%.1f Hz" % s["client_rate_hz"])
    check(dev["rate_hz"] >= 250 and dev["forces"] > 3000, run + ": the Python device at its own rate, the forces back",
          "%.1f Hz, %d forces" % (dev["rate_hz"], dev["forces"]))
    check(sum(dev["refused"].values()) == 0, run + ": the device refused none of the client's forces", json.dumps(dev["refused"]))
    check("device lost (its readings stopped, or a read blocked): forces ramping down" in log, run + ": the device's end is a lost device")
    check("stiffness 1000000000 N/m" in log and "the hand feels" not in log and "virtual coupling: k" in log,
          run + ": the simulated hand gives no real stiffness limit and feels the whole coupling")
    last = igmslog.read(os.path.join(d, "session.lcmlog")).client_status[-1]
    check(last.force_scale == 0.0 and max(abs(f) for f in last.rendered_force) == 0.0,
          run + ": its force ramped out", "scale %.2f, force %s" % (last.force_scale, list(last.rendered_force)))
    latency(run)  # with the logger (and the bad sender) on the same 2 cores: printed, not held
    m = re.search(r"IGMS_DEVICE_READING: (\d+) readings taken; refused (\d+) undecodable, (\d+) out of range, "
                  r"(\d+) out of order; message check: accepted (\d+), refused (\d+)(?: \(([^)]*)\))?", log)
    check(m is not None, run + ": the client's exit line counts the readings", m.group(0) if m else log[-300:])
    if not m:
        continue
    taken, undecodable, out_of_range, out_of_order, acc, ref = (int(m.group(i)) for i in range(1, 7))
    why = dict((k, int(v)) for k, v in (p.split() for p in m.group(7).split(", "))) if m.group(7) else {}
    if run == "alone":
        check(ref == 0 and undecodable + out_of_range + out_of_order == 0 and taken >= 1900,
              "alone: every reading taken, none refused", m.group(0))
    else:
        bad = json.load(open(os.path.join(d, "bad.json")))
        most = lambda n: int(0.9 * n)  # UDP may drop a few
        # The client pinned the good device's sender (its first reading): a second key holder's readings
        # (NaN, out of range, out of order, undecodable) are refused at the message check, before their values.
        signed_bad = bad["nan"] + bad["out_of_range"] + bad["out_of_order"] + bad["undecodable"]
        check(why.get("other_sender", 0) >= most(signed_bad) and undecodable + out_of_range + out_of_order == 0,
              "a second signer's readings refused: the client is pinned to its device",
              "sent %s; %s" % (json.dumps(bad), m.group(0)))
        check(why.get("unsigned", 0) >= most(bad["unsigned"]) and why.get("bad_signature", 0) >= most(bad["other_key"]),
              "unsigned and foreign readings refused by the message check", json.dumps(why))
        check(taken >= 1900, "the good device's readings still taken", "%d" % taken)
a, b = (json.load(open(os.path.join(work, r, "summary.json"))) for r in ("alone", "bad"))
# The simulated hand feels the force the client renders from its estimate, so the largest force spreads by
# run (6.7-11.1 N here, as the scripted device's 7.0-9.3 N): the outcome is what must not change.
check(a["collision_free"] and b["collision_free"] and a["reached_wall"] == b["reached_wall"],
      "the bad readings change nothing: collision-free both times, the same end",
      "largest force %.2f N alone, %.2f N beside them" % (a["max_force_on_robot_N"], b["max_force_on_robot_N"]))
print("lcm_device_test:", "ok" if not fails else "%d failed" % fails)
sys.exit(1 if fails else 0)
PY
