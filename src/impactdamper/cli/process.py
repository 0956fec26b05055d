"""The command line's process: :func:`run` (the ``impactdamper`` console script and ``python -m
impactdamper``) sets one BLAS thread, runs :func:`impactdamper.cli.commands.main` and flushes
its output, a write error ending as one line on stderr and status 1."""

from __future__ import annotations

import contextlib
import os
import sys

from impactdamper.cli.commands import main
from impactdamper.cli.output import output_failed

__all__ = ["run"]


def _one_blas_thread() -> None:
    """One thread in each OpenBLAS loaded (numpy's and scipy's), unless the user set a number.

    The solver's matrices are 4 x 4: BLAS threads never help them, and on a loaded machine the
    thread hand-offs made the matrix-exponential path up to ~90 times slower (tests/conftest.py),
    so that ``steady --theta 1e-9`` took 130 s to reach its work bound instead of 3 s. The
    environment variable must be set before numpy loads, which the package import has done by
    now: set the count in the loaded libraries instead (what threadpoolctl does). Linux only;
    elsewhere, or if anything fails, nothing changes.
    """
    if any(name in os.environ for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")):
        return
    import ctypes

    with contextlib.suppress(OSError):
        with open("/proc/self/maps") as maps:
            paths = {line.split()[-1] for line in maps if "openblas" in line.rsplit("/", 1)[-1].lower()}
        for path in sorted(paths):
            with contextlib.suppress(OSError):
                lib = ctypes.CDLL(path)
                for symbol in (
                    "scipy_openblas_set_num_threads64_",
                    "scipy_openblas_set_num_threads",
                    "openblas_set_num_threads64_",
                    "openblas_set_num_threads",
                ):
                    if hasattr(lib, symbol):
                        getattr(lib, symbol)(1)
                        break


def run(argv: list[str] | None = None) -> int:
    """``impactdamper`` and ``python -m impactdamper``: :func:`main`, and the output flushed, with a write error (a
    closed pipe as in ``| head -c 1``, a full disk) as one line on stderr and status 1 instead of
    a traceback."""
    _one_blas_thread()
    try:
        status = main(argv)
        if sys.stdout is not None:
            sys.stdout.flush()
    except SystemExit as exit_:  # argparse's usage errors and --help; bad values
        status = exit_.code
        try:
            if sys.stdout is not None:
                sys.stdout.flush()
        except OSError as err:
            return output_failed(err)
    except OSError as err:  # writing the help or the result (nothing else here writes files)
        return output_failed(err)
    return status
