"""The igms module's tests: run by ctest (label python) with the project's .venv, PYTHONPATH=build/python,
from the repository's root (so scenes/ and models/ resolve as in the docs)."""
import os
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


def robot(path):
    """A model from example-robot-data (scripts/setup/fetch_robots.sh), or a skip without it."""
    full = os.path.join(ROOT, "third_party", "example-robot-data", "robots", path)
    if not os.path.exists(full):
        pytest.skip(f"{path}: example-robot-data is not fetched (scripts/setup/fetch_robots.sh)")
    return full


_exit_status = {}


def pytest_sessionfinish(session, exitstatus):
    _exit_status["code"] = int(exitstatus)


def pytest_unconfigure(config):
    """Out with pytest's own status, without the interpreter's teardown: pyarrow's threads (the sweep tests
    read Parquet) can abort it after every test has passed (apache/arrow#34314; igms.sweep_cli.run)."""
    if "code" in _exit_status:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_exit_status["code"])
