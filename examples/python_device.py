#!/usr/bin/env python3
"""A haptic device in Python, on the bus: igms-haptic --device lcm[:NAME].

It publishes device_reading_t on NAME_READING at its own rate and renders the
device_force_t the client sends back on NAME_FORCE. Here the "device" is
simulated: a tip held by a hand (a mass on a spring-damper, the scripted
device's hand) that follows timed targets and feels the rendered force. A lab
replaces `Hand` with its device's SDK calls (read the tip, set the force).

    PYTHONPATH=build/python:python $(scripts/setup/python_env.sh) examples/python_device.py \\
        --targets examples/device_plugin/paper_push.targets --lcm-url 'udpm://239.255.76.67:7667?ttl=0'

The targets file is the example device plugin's (igms-haptic --export-targets
writes one): "hand MASS K B", "T X Y Z" (device frame, m), "button T DOWN".
With IGMS_KEY_FILE (or --key-file) it signs its readings and checks the
client's forces (python/igmsbus.py). At exit it prints, and with --stats
writes as JSON, its rate and the reading -> force latency: from a reading's
time to the first force that used it, p50 and p99, and the part of it the bus
adds (the reading's age when the client's cycle read it, plus the force's way
back); the rest is the servo cycle itself, which any device has.

Needs `lcm` (PyPI; scripts/setup/python_env.sh) and the generated types (build/python
or the installed package); with a key, `cryptography` (python3-cryptography).
"""
import argparse
import json
import os
import sys
import time

import lcm

from igms import device_force_t, device_reading_t


def load_targets(path):
    hand, targets, buttons = None, [], []
    for n, line in enumerate(open(path), 1):
        words = line.split()
        if not words or words[0].startswith("#") or words[0] == "end":
            continue
        try:
            if words[0] == "hand":
                hand = tuple(float(w) for w in words[1:4])
            elif words[0] == "button":
                buttons.append((float(words[1]), int(words[2])))
            else:
                t, x, y, z = (float(w) for w in words[:4])
                if targets and t <= targets[-1][0]:
                    raise ValueError("times must increase")
                targets.append((t, (x, y, z)))
        except (ValueError, IndexError) as e:
            sys.exit("python_device: %s:%d: %s (%s)" % (path, n, line.strip(), e))
    if not targets:
        sys.exit("python_device: %s: no targets" % path)
    return hand or (0.3, 400.0, 25.0), targets, buttons


def target_at(targets, t):
    """The scripted device's target: a smooth step between the targets around t."""
    if t <= targets[0][0]:
        return targets[0][1]
    for (t0, a), (t1, b) in zip(targets, targets[1:]):
        if t <= t1:
            u = (t - t0) / (t1 - t0)
            s = u * u * (3 - 2 * u)
            return tuple(a[i] + s * (b[i] - a[i]) for i in range(3))
    return targets[-1][1]


class Hand:
    """m xdd = k (target - x) - b xd + F, semi-implicit Euler: the device's tip as a person moves it."""

    def __init__(self, mass, k, b, start):
        self.m, self.k, self.b = mass, k, b
        self.x, self.v = list(start), [0.0, 0.0, 0.0]

    def step(self, goal, force, dt):
        for i in range(3):
            a = (self.k * (goal[i] - self.x[i]) - self.b * self.v[i] + force[i]) / self.m
            self.v[i] += dt * a
            self.x[i] += dt * self.v[i]


def quantile(values, q):
    s = sorted(values)
    return s[min(len(s) - 1, int(q * len(s)))] if s else float("nan")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--targets", required=True, help="the targets file (examples/device_plugin/paper_push.targets)")
    p.add_argument("--lcm-url", default="udpm://239.255.76.67:7667?ttl=0")
    p.add_argument("--name", default="IGMS_DEVICE", help="channel base: NAME_READING out, NAME_FORCE in")
    p.add_argument("--rate", type=float, default=500.0, help="readings per second")
    p.add_argument("--duration", type=float, default=0.0, help="seconds (0: until the targets end, plus 1 s)")
    p.add_argument("--key-file", default=os.environ.get("IGMS_KEY_FILE", ""), help="the bus key (IGMS_KEY_FILE)")
    p.add_argument("--max-force", type=float, default=3.3, help="N the device renders (sent with each reading)")
    p.add_argument("--max-stiffness", type=float, default=1e9,
                   help="N/m the device renders stably (a real device's, e.g. an Omni's 800; a stiffer coupling is "
                        "felt scaled down to it). The default, 1e9, is no limit: this hand is simulated, as the "
                        "scripted device's")
    p.add_argument("--stats", help="write the rate and latency figures here (JSON)")
    p.add_argument("--warm-up", type=float, default=1.0, help="s at the start left out of the latency figures")
    a = p.parse_args()

    (mass, k, b), targets, buttons = load_targets(a.targets)
    duration = a.duration or targets[-1][0] + 1.0
    signer = verifier = None
    if a.key_file:
        import igmsbus
        try:
            key = igmsbus.read_key_file(a.key_file)
        except (OSError, ValueError) as e:
            sys.exit("python_device: --key-file %s" % e)
        signer, verifier = igmsbus.Signer(key), igmsbus.Verifier(key)
    lc = lcm.LCM(a.lcm_url)
    reading_channel, force_channel = a.name + "_READING", a.name + "_FORCE"
    sent_at = {}      # reading seq -> its utime (us)
    latency_us = []   # reading -> the first force that used it, here
    added_us = []     # the part the bus adds: reading -> the cycle that read it, and the force's way back
    age_us, back_us = [], []
    newest_used = [-1]
    force = [0.0, 0.0, 0.0]
    forces = [0]

    def on_force(channel, data):
        if verifier is not None:
            data = verifier.check(channel, data)
            if data is None:
                return
        try:
            m = device_force_t.decode(data)
        except Exception:  # untrusted bytes (a decoder may raise anything): refuse, never fall over
            return
        forces[0] += 1
        force[:] = [f if f == f else 0.0 for f in m.force[:3]]  # NaN-safe
        if m.reading_seq > newest_used[0] and m.reading_seq in sent_at:
            now_us = time.time() * 1e6
            if time.perf_counter() - start >= a.warm_up:
                latency_us.append(now_us - sent_at[m.reading_seq])
            if time.perf_counter() - start >= a.warm_up:  # the first second: imports, page faults, joins
                added_us.append(m.reading_age_us + (now_us - m.utime))
                age_us.append(m.reading_age_us)
                back_us.append(now_us - m.utime)
            newest_used[0] = m.reading_seq

    lc.subscribe(force_channel, on_force)
    hand = Hand(mass, k, b, target_at(targets, 0.0))
    msg = device_reading_t()
    msg.orientation = [1.0, 0.0, 0.0, 0.0]
    msg.max_force = a.max_force
    msg.max_stiffness = a.max_stiffness
    period = 1.0 / a.rate
    start = time.perf_counter()
    seq, last = 0, 0.0
    while True:
        now = time.perf_counter() - start
        if now >= duration:
            break
        hand.step(target_at(targets, now), force, min(0.01, now - last) if seq else 0.0)
        last = now
        seq += 1
        msg.utime = int(time.time() * 1e6)
        msg.seq = seq
        msg.position = list(hand.x)
        msg.velocity = list(hand.v)
        msg.buttons = next((d for t, d in reversed(buttons) if now >= t), 0) & 1
        data = msg.encode()
        lc.publish(reading_channel, signer.sign(reading_channel, data) if signer else data)
        sent_at[seq] = msg.utime
        sent_at.pop(seq - 2000, None)
        # Forces until the next reading is due (absolute deadlines: the rate holds; the client's forces
        # come every millisecond, so waiting on them is never late by more than one).
        while time.perf_counter() < start + seq * period:
            lc.handle_timeout(1)
    wall = time.perf_counter() - start
    stats = {"readings": seq, "rate_hz": seq / wall, "forces": forces[0],
             "latency_us_p50": quantile(latency_us, 0.5), "latency_us_p99": quantile(latency_us, 0.99),
             "latency_samples": len(latency_us),
             "added_us_p50": quantile(added_us, 0.5), "added_us_p99": quantile(added_us, 0.99),
             "reading_age_us_p50": quantile(age_us, 0.5), "reading_age_us_p99": quantile(age_us, 0.99),
             "force_way_us_p50": quantile(back_us, 0.5), "force_way_us_p99": quantile(back_us, 0.99),
             "refused": verifier.refused if verifier else None}
    print("python_device: %d readings in %.2f s (%.1f Hz), %d forces; reading -> force p50 %.0f us, p99 %.0f us, "
          "of which the bus adds p50 %.0f us, p99 %.0f us" % (seq, wall, stats["rate_hz"], forces[0],
                                                               stats["latency_us_p50"], stats["latency_us_p99"],
                                                               stats["added_us_p50"], stats["added_us_p99"]),
          file=sys.stderr)
    if a.stats:
        json.dump(stats, open(a.stats, "w"))


if __name__ == "__main__":
    main()
