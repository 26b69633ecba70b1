#!/usr/bin/env python3
"""python/igmsbus.py's read_key_file refuses what bus/bus_key.cc refuses, each with a line naming the file:
a symbolic link (to a good key), a key another user owns (as root), one others can read, a folder; and
reads a good one."""
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import igmsbus  # noqa: E402


def error_of(path):
    try:
        igmsbus.read_key_file(path)
    except ValueError as e:
        return str(e)
    return ""


def main():
    failures = []
    with tempfile.TemporaryDirectory() as d:
        def write(name, text, mode):
            path = os.path.join(d, name)
            with open(path, "w") as f:
                f.write(text)
            os.chmod(path, mode)
            return path

        good = write("good.key", "ab" * 32 + "\n", 0o600)
        cases = [(good, "")]
        os.symlink(good, os.path.join(d, "link.key"))
        cases.append((os.path.join(d, "link.key"), "link.key: a symbolic link; give the key file itself"))
        cases.append((write("open.key", "ab" * 32, 0o644), "open.key: readable by others (mode 644); chmod 600 it"))
        cases.append((write("short.key", "abcd", 0o600), "short.key: not a bus key"))
        cases.append((d, "not a regular file"))
        if os.geteuid() == 0:
            theirs = write("theirs.key", "ab" * 32, 0o600)
            os.chown(theirs, 65534, 65534)
            cases.append((theirs, "theirs.key: owned by uid 65534, not by this user (uid 0)"))
        for path, expected in cases:
            got = error_of(path)
            if (expected == "" and got != "") or (expected and expected not in got):
                failures.append("%s: expected %r, got %r" % (os.path.basename(path), expected, got))
        if igmsbus.read_key_file(good) != bytes([0xab]) * 32:
            failures.append("the good key reads wrong")
    for f in failures:
        print("FAIL:", f)
    print("%d key files checked" % len(cases))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
