"""The igms module's tests: run by ctest (label python) with the project's .venv, PYTHONPATH=build/python,
from the repository's root (so scenes/ and models/ resolve as in the docs)."""
import os

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


def robot(path):
    """A model from example-robot-data (scripts/fetch_robots.sh), or a skip without it."""
    full = os.path.join(ROOT, "third_party", "example-robot-data", "robots", path)
    if not os.path.exists(full):
        pytest.skip(f"{path}: example-robot-data is not fetched (scripts/fetch_robots.sh)")
    return full
