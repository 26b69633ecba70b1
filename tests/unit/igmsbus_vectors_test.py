#!/usr/bin/env python3
"""python/igmsbus.py against the shared signed-bus vectors (tests/data/bus_vectors.json), which
bus/message_verifier passes too (tests/unit/bus_vectors_test.cc): the same exact signatures, and the
same verdict at every step of every sequence (the replay window, staleness, forged and unsigned
messages, replays, the sender table's bound and when a silent sender is forgotten)."""
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "python"))
import igmsbus  # noqa: E402

failures = []


def sender(k):
    return bytes([k & 255, (k >> 8) & 255] + [0] * 14)


def message(doc, step, k):
    key = bytes.fromhex(doc["other_key"] if step.get("other_key") else doc["key"])
    payload = bytes([1, 2])
    if step.get("unsigned"):
        return payload
    signed_us = doc["base_us"] + int(round(step.get("signed_s", step["at_s"]) * 1e6))
    m = bytearray(igmsbus.sign_as(key, sender(k), step["counter"], signed_us, step.get("channel", "C"), payload,
                                  replayed=step.get("replayed", False)))
    if "tamper" in step:
        m[step["tamper"]] ^= 1
    return bytes(m)


def main():
    doc = json.load(open(os.path.join(here, "..", "data", "bus_vectors.json")))
    key = bytes.fromhex(doc["key"])
    for v in doc["signatures"]:
        got = igmsbus.sign_as(key, bytes.fromhex(v["sender"]), v["counter"], v["time_us"], v["channel"],
                              bytes.fromhex(v["payload"]), replayed=v["replayed"])
        if got.hex() != v["message"]:
            failures.append("signature of counter %d on %s differs" % (v["counter"], v["channel"]))
        taken = igmsbus.Verifier(key, accept_replays=True).check_at(v["channel"], bytes.fromhex(v["message"]),
                                                                    v["time_us"], 0.0)
        if taken != bytes.fromhex(v["payload"]):
            failures.append("the vector of counter %d on %s is not taken" % (v["counter"], v["channel"]))
    steps = 0
    for seq in doc["sequences"]:
        verifier = igmsbus.Verifier(key, accept_replays=seq.get("accept_replays", False))
        for i, step in enumerate(seq["steps"]):
            first, last = step.get("senders", [step.get("sender"), step.get("sender")])
            for k in range(first, last + 1):
                before = dict(verifier.refused)
                now_us = doc["base_us"] + int(round(step["at_s"] * 1e6))
                payload = verifier.check_at(step.get("channel", "C"), message(doc, step, k), now_us, float(step["at_s"]))
                got = "accepted" if payload is not None else next(r for r in verifier.refused
                                                                  if verifier.refused[r] != before[r])
                steps += 1
                if got != step["expect"]:
                    failures.append("%s, step %d (sender %d): %s, expected %s" % (seq["name"], i, k, got,
                                                                                   step["expect"]))
    for f in failures:
        print("FAIL:", f)
    print("igmsbus_vectors_test: %d signatures, %d steps in %d sequences, %d failures"
          % (len(doc["signatures"]), steps, len(doc["sequences"]), len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
