"""The CPU time the hypervisor took from this virtual machine ("steal", /proc/stat), as a share of the
machine's time over an interval. A loop at SCHED_FIFO cannot keep time while its virtual CPU is not running;
a timed run that misses its goals during such a spell judges the host, not the code."""
import os
import time

TICK = os.sysconf("SC_CLK_TCK")
CPUS = os.cpu_count() or 1


def steal_ticks(stat="/proc/stat"):
    """The steal column of /proc/stat's aggregate line (ticks of 1/TICK s over every CPU); 0 where the
    kernel does not count it."""
    with open(stat) as f:
        fields = f.readline().split()
    return int(fields[8]) if fields[0] == "cpu" and len(fields) > 8 else 0


class StealMeter:
    """The share of every CPU's time stolen between start() and share()."""

    def start(self):
        self.ticks, self.at = steal_ticks(), time.monotonic()
        return self

    def share(self):
        elapsed = time.monotonic() - self.at
        return (steal_ticks() - self.ticks) / TICK / (elapsed * CPUS) if elapsed > 0 else 0.0


def wait_for_quiet(threshold, window=1.0, patience=120.0):
    """Waits until a window of `window` s steals at most `threshold` of the machine, for at most `patience`
    s; returns the last window's share."""
    deadline = time.monotonic() + patience
    while True:
        meter = StealMeter().start()
        time.sleep(window)
        share = meter.share()
        if share <= threshold or time.monotonic() >= deadline:
            return share
