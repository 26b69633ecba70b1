"""What the Python crosschecks against the peers in .venv-peers share: the
command line (BUILD_DIR SOURCE_DIR), the peers' interpreter, and checks that
print ok/FAIL and fail the test at the end."""
import os
import sys


class PeerCheck:
    def __init__(self, argv):
        self.build, self.source = argv[1], argv[2]
        self.accuracy = os.path.join(self.build, "tools", "igms-accuracy")
        self.python = os.path.join(self.source, ".venv-peers", "bin", "python")
        self.failures = []
        if not os.path.exists(self.python):
            sys.exit(f"{self.python} is missing: scripts/setup/peer_env.sh installs it (scripts/setup/setup.sh runs it)")

    def check(self, ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            self.failures.append(what)

    def finish(self, name):
        if self.failures:
            sys.exit(f"{len(self.failures)} checks failed")
        print(f"{name}: all checks passed")
