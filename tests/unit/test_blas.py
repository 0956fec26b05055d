"""One BLAS thread in a workflow job and in the command line (impactdamper.core.blas)."""

import json
import os
import subprocess
import sys

import pytest

from impactdamper.core import blas


def _child(code: str, **env) -> str:
    environment = {k: v for k, v in os.environ.items() if k not in blas.BLAS_THREAD_VARIABLES} | env
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, env=environment
    ).stdout.strip()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="OpenBLAS's count is set through /proc/self/maps")
def test_a_job_with_two_threads_runs_one_blas_thread_and_hands_one_on():
    # Snakemake sets a job's BLAS counts to its threads (2 here): before this, each of a job's two
    # worker processes ran two BLAS threads, at three times the processor time of one process.
    code = (
        "import json, os, numpy; from impactdamper.core import blas; before = blas.blas_threads();"
        " blas.one_blas_thread(force=True);"
        " print(json.dumps([before, blas.blas_threads(), os.environ['OPENBLAS_NUM_THREADS'], os.environ['OMP_NUM_THREADS']]))"
    )
    before, after, *variables = json.loads(_child(code, OPENBLAS_NUM_THREADS="2", OMP_NUM_THREADS="2"))
    # (numpy's OpenBLAS and scipy's, which the package loads too)
    assert before and set(before) == {2} and after == [1] * len(before) and variables == ["1", "1"]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="OpenBLAS's count is set through /proc/self/maps")
def test_the_command_lines_one_thread_yields_to_a_users_count():
    code = "import json, numpy; from impactdamper.core import blas; blas.one_blas_thread(); print(json.dumps(blas.blas_threads()))"
    user = json.loads(_child(code, OPENBLAS_NUM_THREADS="2"))
    assert user and set(user) == {2}
    assert set(json.loads(_child(code))) == {1}


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="OpenBLAS's count is set through /proc/self/maps")
def test_a_blas_that_loads_after_the_command_lines_setting_runs_one_thread():
    """scipy's own OpenBLAS, loaded on first use after one_blas_thread ran, started 2 threads on
    two cores (the matrix-exponential path of `lyapunov --omega 2e4`: 7.3 CPU-s in 4.1 s)."""
    code = (
        "import json, numpy; from impactdamper.core import blas; blas.one_blas_thread(); first = blas.blas_threads();"
        " import scipy.linalg; print(json.dumps([first, blas.blas_threads()]))"
    )
    first, after = json.loads(_child(code))
    assert len(after) == len(first) + 1 and set(after) == {1}
