"""Shared by the workflow's tests: one dry run of the whole DAG (~5 s), planned once per session.

Every job forced, with the CI config (``-n --forceall -p --configfile config/ci.yaml``): the
stages' tests read its listing (rules, inputs, outputs, logs, threads) instead of each planning
the DAG again.
"""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def ci_dry_run() -> str:
    """The dry run's standard output (the jobs' listing); it must succeed."""
    out = subprocess.run(
        [sys.executable, "-m", "snakemake", "--nolock", "-n", "--cores", "2", "--forceall", "-p"]
        + ["--configfile", "config/ci.yaml"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    return out.stdout
