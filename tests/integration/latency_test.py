#!/usr/bin/python3
"""The haptic loop across a rehearsed network, over the real bus: igms-server on
its realtime clock, igms-relay delaying, jittering and dropping both directions,
igms-haptic on the paper's push and pull scripts (scripts/bench/latency_bench.py
--quick). Each case must hold the servo rate, never step the rendered force by
more than 1 N a cycle, never declare the server lost, keep the passivity
observer's energy balance where physics alone puts it, and start its script
where the arm's motion starts (the client waits for the server, so the pushes
meet the same part of the motion in every run). The push at 0 ms and at 5 ms
with loss, and the pull 20 ms away (+-10 ms), end collision-free at the wall.
The push 20 +-10 ms away collides: with the jitter the hand's inputs reach the
server in bursts, and the tip retreating from the first push at about 3 m/s, which
grazes the arm at 0 ms, appears 2 cm inside it at once; the server's push jumps
to its 40 N cap and throws the arm (docs/client.md). The test asserts that kick,
so a change that removes it is seen; every case reaches the wall. The bus is
signed (a new key in IGMS_KEY_FILE for every process): the relay's reordering
and loss must not make a receiver refuse a genuine message.
  latency_test.py BUILD_DIR   (inside scripts/netns_run.sh)"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    build = os.path.abspath(sys.argv[1])
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        key = os.path.join(tmp, "bus.key")
        with os.fdopen(os.open(key, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600), "w") as f:
            f.write(os.urandom(32).hex() + "\n")
        os.environ["IGMS_KEY_FILE"] = key  # every process the bench starts signs and checks
        out = os.path.join(tmp, "results.json")
        subprocess.run([sys.executable, os.path.join(ROOT, "scripts/bench/latency_bench.py"), "--quick", "--build", build,
                        "--out", tmp, "--port", "7850", "--json", out], check=True)
        for r in json.load(open(out)):
            case = f"{r['experiment']} at {r['delay_ms']:g} ms +-{r['jitter_ms']:g} ms, {r['loss'] * 100:g} % loss"

            def check(ok, what):
                print(f"{'ok  ' if ok else 'FAIL'} {case}: {what}")
                if not ok:
                    failures.append(f"{case}: {what}")

            check(r["cycles"] == 7000, f"the client ran its 7000 cycles ({r['cycles']})")
            check(r["bus_refused"] == 0 and r["bus_accepted"] > 5000,
                  f"signed, through reordering and loss: {r['bus_accepted']} accepted, {r['bus_refused']} refused")
            check(r["rate_hz"] is not None and r["rate_hz"] >= 950, f"servo rate {r['rate_hz']} Hz >= 950 Hz")
            check(r["max_force_step_N"] is not None and r["max_force_step_N"] <= 1.0 + 1e-9,
                  f"largest force step {r['max_force_step_N']} N <= 1 N")
            # Lost means no state for 50 ms. The path alone never does that (its delay varies by the jitter
            # at most); a stall of the whole machine can, and then declaring it is right: a clean-clone CI
            # run on a loaded 2-core VM saw it once, on the pull 20 ms away. Such a gap shows in the oldest
            # state the client held (the arrival gap plus the path's shortest delay).
            stalled = r["state_age_max_ms"] is not None and r["state_age_max_ms"] >= r["delay_ms"] - r["jitter_ms"] + 50
            check(not r["server_lost"] or stalled,
                  f"the server was declared lost only after states stopped for 50 ms (oldest state held "
                  f"{r['state_age_max_ms']} ms)")
            # A pile-up (states queued behind each other, e.g. LCM's 30-deep queue read oldest first) ages every
            # state: it shows in the median. Measured idle: p50 1.1 ms at 0 ms, 13.2 at 20 +-10 (the newest of
            # jittered states), 4.2 at 5 +-2.5. A stall of the whole machine ages only the states around it: the
            # p99 allows it (a clean-clone CI run on a loaded 2-core VM saw p99 21 ms at 0 ms delay, p50 not shown).
            check(r["state_age_p50_ms"] is not None and r["state_age_p50_ms"] < r["delay_ms"] + 3,
                  f"state age p50 {r['state_age_p50_ms']} ms is the path's delay, not a pile-up")
            check(r["state_age_p99_ms"] is not None and r["state_age_p99_ms"] < r["delay_ms"] + r["jitter_ms"] + 25,
                  f"state age p99 {r['state_age_p99_ms']} ms within the path's delay and jitter + 25 ms of stalls")
            # No energy made by delay: the balance stays near the zero-delay push's -17 mJ (the robot handing back
            # its own motion); the controller holds it at -25 mJ, and its 1 N cap may let a cycle's worth past.
            check(r["lowest_energy_mJ"] is not None and r["lowest_energy_mJ"] >= -30.0,
                  f"lowest energy balance {r['lowest_energy_mJ']} mJ >= -30 mJ")
            # The client starts its script on the server's first status (0.11-0.25 s into the motion here);
            # started after the server, as this bench once did, it began 0.16-0.42 s in on an idle machine and
            # later on a loaded one, and whether a delayed push landed depended on that (a CI run whose first
            # push gave no force collided; its start was not recorded). The bound leaves a loaded machine room.
            check(r["first_input_s"] is not None and r["first_input_s"] <= r["delay_ms"] / 1000 + 0.5,
                  f"the script began with the motion: its first input taken {r['first_input_s']} s in")
            kicked = r["experiment"] == "push" and r["delay_ms"] == 20
            outcome = (f"first collision at {r['first_collision_s']} s; the two pushes' largest forces "
                       f"{r['push_peaks_N']} N, the retreat's {r['retreat_peak_N']} N")
            check(r["reached_wall"], "reached the wall")
            if kicked:  # measured: 38.0-40.0 N in 7 of 7 runs (0 N at 0 ms, 0.4-3.4 N at 5 ms)
                check(r["retreat_peak_N"] is not None and r["retreat_peak_N"] >= 30.0,
                      f"the retreat kicks the arm near the server's 40 N cap ({outcome}; collision-free "
                      f"{r['collision_free']})")
                continue
            check(r["collision_free"], "collision-free" if r["collision_free"] else f"collision-free ({outcome}; "
                  f"oldest state held {r['state_age_max_ms']} ms)")
    if failures:
        print(f"{len(failures)} checks failed", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
