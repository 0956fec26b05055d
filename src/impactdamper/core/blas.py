"""One BLAS thread in this process: the solver's matrices are 4 x 4, so BLAS threads never help
them, and on a loaded machine OpenBLAS's thread hand-offs made the matrix-exponential path up to
~90 times slower (tests/conftest.py). A workflow job's parallel work is its own worker processes
(its ``threads``), and Snakemake sets the BLAS thread counts of a job to its threads: a job on two
processes ran four BLAS threads on two cores, at three times the processor time of one process.
"""

from __future__ import annotations

import contextlib
import os

__all__ = ["BLAS_THREAD_VARIABLES", "one_blas_thread", "blas_threads"]

# The variables the BLAS libraries read when they load (a process started later reads them too).
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
_SET = (
    "scipy_openblas_set_num_threads64_",
    "scipy_openblas_set_num_threads",
    "openblas_set_num_threads64_",
    "openblas_set_num_threads",
)
_GET = (
    "scipy_openblas_get_num_threads64_",
    "scipy_openblas_get_num_threads",
    "openblas_get_num_threads64_",
    "openblas_get_num_threads",
)


def _openblas_libraries() -> list:
    """The OpenBLAS libraries loaded in this process (numpy's and scipy's), from /proc/self/maps
    (Linux; elsewhere none)."""
    import ctypes

    with contextlib.suppress(OSError):
        with open("/proc/self/maps") as maps:
            paths = {line.split()[-1] for line in maps if "openblas" in line.rsplit("/", 1)[-1].lower()}
        out = []
        for path in sorted(paths):
            with contextlib.suppress(OSError):
                out.append(ctypes.CDLL(path))
        return out
    return []


def one_blas_thread(force: bool = False) -> None:
    """One thread in each OpenBLAS loaded and in each that loads later (the variables set to 1,
    read by a library when it loads, and by the processes this one starts), unless the user set
    a number (``force``: whatever is set).

    The environment variables must be set before numpy loads, which the package import has done
    by the time this runs: the count is set in the loaded libraries instead (what threadpoolctl
    does). Linux only; elsewhere, or if anything fails, the loaded libraries keep theirs.
    """
    if not force and any(name in os.environ for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")):
        return
    # The variables set to 1 as well: a BLAS that loads later reads them when it loads (scipy's
    # own OpenBLAS, loaded on first use after this ran, started 2 threads on two cores and the
    # matrix-exponential path took 7.3 CPU-s in 4.1 s for `lyapunov --omega 2e4`).
    os.environ.update(dict.fromkeys(BLAS_THREAD_VARIABLES, "1"))
    for lib in _openblas_libraries():
        _call(lib, _SET, 1)


def blas_threads() -> list[int]:
    """The thread count of each OpenBLAS loaded (for the tests)."""
    return [int(_call(lib, _GET)) for lib in _openblas_libraries() if any(hasattr(lib, s) for s in _GET)]


def _call(lib, symbols: tuple, *args):
    """The first of ``symbols`` that ``lib`` exports, called (the names differ between builds)."""
    for symbol in symbols:
        if hasattr(lib, symbol):
            return getattr(lib, symbol)(*args)
    return None
