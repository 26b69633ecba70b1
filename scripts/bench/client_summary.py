"""Reads igms-haptic's closing lines (haptic_client/app/haptic_client.cc, printSummary) for the benches that
judge a run by them. A quantile the client's histogram cannot place prints as "> LIMIT" (servo_stats.h,
quantileText: the state age's histogram ends at 200 ms, the jitter's at 20 ms); it reads as infinity here, so
a bound on it fails and the maximum, always printed as a number, still says how long the longest gap was."""
import math
import re

NUMBER = r"(>\s*)?([-\d.]+)"


def _quantile(beyond, value):
    return math.inf if beyond else float(value)


def read(log):
    """The summary's figures (None where a line is missing): cycles, rate_hz, max_force_step_N,
    cut_to_bound; state_age_p50_ms, state_age_p99_ms, state_age_max_ms, lowest_energy_J, passivity_cycles;
    late_cycles; jitter_p50_us, jitter_p99_us, jitter_max_us; fifo (every thread on SCHED_FIFO)."""
    out = dict.fromkeys(["cycles", "rate_hz", "max_force_step_N", "cut_to_bound", "state_age_p50_ms",
                         "state_age_p99_ms", "state_age_max_ms", "lowest_energy_J", "passivity_cycles",
                         "late_cycles", "jitter_p50_us", "jitter_p99_us", "jitter_max_us"])
    m = re.search(r"(\d+) cycles in ([\d.]+) s \(([\d.]+) Hz\), (\d+) deadline misses.*max force step ([\d.]+) N "
                  r"\((\d+) cycles cut", log)
    if m:
        out.update(cycles=int(m.group(1)), rate_hz=float(m.group(3)), max_force_step_N=float(m.group(5)),
                   cut_to_bound=int(m.group(6)))
    a = re.search(rf"state age p50 {NUMBER} ms, p99 {NUMBER} ms, max ([\d.]+) ms; lowest energy balance ([-\d.]+) "
                  r"J, passivity controller acted in (\d+) cycles", log)
    if a:
        out.update(state_age_p50_ms=_quantile(a.group(1), a.group(2)),
                   state_age_p99_ms=_quantile(a.group(3), a.group(4)), state_age_max_ms=float(a.group(5)),
                   lowest_energy_J=float(a.group(6)), passivity_cycles=int(a.group(7)))
    late = re.search(r"(\d+) cycles started over a period late", log)
    if late:
        out["late_cycles"] = int(late.group(1))
    j = re.search(rf"cycle jitter p50 {NUMBER} us, p99 {NUMBER} us, max ([\d.]+) us", log)
    if j:
        out.update(jitter_p50_us=_quantile(j.group(1), j.group(2)), jitter_p99_us=_quantile(j.group(3), j.group(4)),
                   jitter_max_us=float(j.group(5)))
    out["fifo"] = "igms-haptic: every thread on SCHED_FIFO" in log
    return out
