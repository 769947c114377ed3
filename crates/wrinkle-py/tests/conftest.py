"""Shared fixtures: the CLI binary built beside the extension (for results compared with the CLI's)."""

import os
import subprocess
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def cli():
    """Runs `wrinkle ARGS...` and returns its completed process; fails the test on a non-zero exit."""
    exe = os.environ.get("WRINKLE_CLI")
    if not exe:
        pytest.skip("WRINKLE_CLI not set: the CLI was not built in this run")

    def run(*args, check=True):
        p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        if check and p.returncode != 0:
            raise AssertionError(f"wrinkle {' '.join(map(str, args))} failed: {p.stderr}")
        return p

    return run


@pytest.fixture(scope="session")
def repo():
    return Path(os.environ.get("WRINKLE_REPO", Path(__file__).resolve().parents[3]))
