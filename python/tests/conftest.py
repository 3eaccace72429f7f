"""Shared fixtures: the repository, and the `strider` binary the Rust tests built."""

import json
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# Figures read off the wall clock (timing only): they differ between any two runs.
TIMING = ("footstep_planning_ms_p99", "upper_body_ms_per_frame")


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def cli():
    """Runs `strider ARGS…` (the release binary) and returns (exit code, stdout, stderr)."""
    binary = Path(os.environ.get("STRIDER_BIN", REPO / "target" / "release" / "strider"))
    if not binary.exists():
        pytest.fail(f"{binary} is missing: build it with `cargo build --release` (scripts/test does)")

    def run(*args, cwd=REPO):
        p = subprocess.run([str(binary), *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600)
        return p.returncode, p.stdout, p.stderr

    return run


def cli_json(cli, *args):
    code, out, err = cli("run", *args, "--format", "json")
    assert code in (0, 1), err
    return json.loads(out)


def without_timing(doc):
    """`doc` with the wall-clock figures left out."""
    if isinstance(doc, dict):
        return {k: without_timing(v) for k, v in doc.items() if k not in TIMING}
    if isinstance(doc, list):
        return [without_timing(v) for v in doc]
    return doc
