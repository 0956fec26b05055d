"""Progress bars for long commands: a tqdm bar on stderr, only where a person watches.

A command that runs for minutes (``impactdamper response`` with many points, a design chart)
shows a bar on stderr when stderr is a terminal and the user did not ask for quiet; piped or
redirected (a Snakemake log, a test's captured stderr, ``2> file``) it writes nothing, so that
logs and captured output stay the same from run to run.

Usage::

    with progress_bar(total=2 * points, desc="response", quiet=args.quiet) as bar:
        frequency_response(p, ..., on_point=bar.step)
"""

from __future__ import annotations

import sys
from typing import IO

__all__ = [
    "progress_bar",
]


def _shows_progress(quiet: bool = False, stream: IO[str] | None = None) -> bool:
    """Whether a bar is drawn: not ``quiet`` and ``stream`` (default ``sys.stderr``) a terminal."""
    stream = sys.stderr if stream is None else stream
    if quiet:
        return False
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # a closed or file-like stream without a terminal
        return False


class _ProgressBar:
    """A count of done steps out of ``total``, drawn by tqdm on ``stream`` or not at all.

    Use as a context manager; :meth:`step` takes and ignores any arguments, so that it can be
    passed as a library callback (``on_point=bar.step``, ``progress=bar.step``).
    """

    def __init__(
        self, total: int | None, desc: str = "", *, quiet: bool = False, stream: IO[str] | None = None
    ) -> None:
        stream = sys.stderr if stream is None else stream
        self._bar = None
        if _shows_progress(quiet, stream):
            from tqdm import tqdm

            self._bar = tqdm(total=total, desc=desc, file=stream, unit="pt", leave=False, dynamic_ncols=True)

    @property
    def shown(self) -> bool:
        """Whether a bar is drawn."""
        return self._bar is not None

    def step(self, *args: object, **kwargs: object) -> None:
        """One step done."""
        if self._bar is not None:
            self._bar.update(1)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> _ProgressBar:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def progress_bar(
    total: int | None, desc: str = "", *, quiet: bool = False, stream: IO[str] | None = None
) -> _ProgressBar:
    """A :class:`ProgressBar` of ``total`` steps labelled ``desc`` on ``stream`` (default
    stderr), drawn only when the stream is a terminal and ``quiet`` is false."""
    return _ProgressBar(total, desc, quiet=quiet, stream=stream)
