#!/usr/bin/env python3
"""python/igmsbus.py's Signer across a fork: the child signs as a sender of its own, its counter from 1,
so no (sender, counter) pair, a GMAC nonce under one sender's key, is used by both processes; the
child's message verifies, and the parent signs on as before. (Before: the child kept its parent's
sender and counter, and the two signed counter 2 alike.)"""
import os
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import igmsbus  # noqa: E402

KEY = bytes(range(32))


def trailer(message):
    t = len(message) - igmsbus.TRAILER_BYTES
    sender = message[t + 4:t + 20]
    counter, _ = struct.unpack(">QQ", message[t + 20:t + 36])
    return sender, counter


def main():
    signer = igmsbus.Signer(KEY)
    before = signer.sign("IGMS_COMMAND", b"\x09\x08\x07")
    read_end, write_end = os.pipe()
    child = os.fork()
    if child == 0:
        os.close(read_end)
        os.write(write_end, signer.sign("IGMS_COMMAND", b"\x09\x08\x07"))
        os._exit(0)
    os.close(write_end)
    from_child = b""
    while len(from_child) < len(before):
        chunk = os.read(read_end, len(before))
        if not chunk:
            break
        from_child += chunk
    os.close(read_end)
    _, status = os.waitpid(child, 0)
    after = signer.sign("IGMS_COMMAND", b"\x09\x08\x07")
    failures = []
    if os.waitstatus_to_exitcode(status) != 0 or len(from_child) != len(before):
        failures.append("the child did not sign")
    (p_sender, p_counter), (c_sender, c_counter), (a_sender, a_counter) = map(trailer, (before, from_child, after))
    if c_sender == p_sender:
        failures.append("the child signs under its parent's sender")
    if c_counter != 1:
        failures.append("the child's counter goes on from its parent's (%d)" % c_counter)
    if (c_sender, c_counter) == (a_sender, a_counter):
        failures.append("parent and child used one nonce")
    if (a_sender, a_counter) != (p_sender, p_counter + 1):
        failures.append("the parent's sender or counter moved")
    verifier = igmsbus.Verifier(KEY)
    for name, message in (("before", before), ("child", from_child), ("after", after)):
        if verifier.check("IGMS_COMMAND", message) is None:
            failures.append("the %s message does not verify" % name)
    for f in failures:
        print("FAIL:", f)
    print("parent sender %s counters %d, %d; child sender %s counter %d" %
          (p_sender.hex()[:8], p_counter, a_counter, c_sender.hex()[:8], c_counter))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
