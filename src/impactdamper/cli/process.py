"""The command line's process: :func:`run` (the ``impactdamper`` console script and ``python -m
impactdamper``) sets one BLAS thread, runs :func:`impactdamper.cli.commands.main` and flushes
its output, a write error ending as one line on stderr and status 1."""

from __future__ import annotations

import sys

from impactdamper.cli.commands import main
from impactdamper.cli.output import output_failed
from impactdamper.core.blas import one_blas_thread

__all__ = ["run"]


def run(argv: list[str] | None = None) -> int:
    """``impactdamper`` and ``python -m impactdamper``: :func:`main`, and the output flushed, with a write error (a
    closed pipe as in ``| head -c 1``, a full disk) as one line on stderr and status 1 instead of
    a traceback."""
    one_blas_thread()
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
