"""The design call's plumbing: independent tasks run in forked processes, and the progress
messages with the longest wait for one (:func:`impactdamper.studies.design.optimum.design_optima`)."""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from collections.abc import Callable

__all__ = ["in_parallel", "Silences", "processor_time"]


# The tasks of in_parallel's pool, by index (the forked workers inherit them: a task holds
# closures, which cannot be sent through a pipe).
_TASKS: list = []


def _run_task(i: int):
    return _TASKS[i]()


def in_parallel(tasks: dict, workers: int) -> dict:
    """{key: task()} of independent tasks, ``workers`` at a time in forked processes (in this
    one with a single worker), the answers in the tasks' order whatever ran where."""
    keys = list(tasks)
    if workers <= 1 or len(keys) <= 1 or "fork" not in multiprocessing.get_all_start_methods():
        return {k: tasks[k]() for k in keys}
    _TASKS[:] = [tasks[k] for k in keys]
    try:
        with multiprocessing.get_context("fork").Pool(min(workers, len(keys))) as pool:
            results = pool.map(_run_task, range(len(keys)), chunksize=1)
    finally:
        _TASKS.clear()
    return dict(zip(keys, results))


class Silences:
    """Progress messages, passed on, and the longest wait for one: from the call's start to its
    first message, between two messages (whichever process said them), and from the last to the
    end. The last message's time and the longest wait live in memory that forked workers share
    (with ``shared``), so a worker's message counts as the parent's does."""

    def __init__(self, say: Callable[[str], None], shared: bool):
        self._say = say
        self._lock = multiprocessing.Lock() if shared else threading.Lock()
        start = [time.monotonic(), 0.0]  # (the last message's time, the longest wait)
        self._times = multiprocessing.RawArray("d", start) if shared else start

    def __call__(self, message: str) -> None:
        with self._lock:
            now = time.monotonic()
            self._times[1] = max(self._times[1], now - self._times[0])
            self._times[0] = now
        self._say(message)

    def longest(self) -> float:
        """The longest wait so far, the one since the last message included, s."""
        with self._lock:
            return max(self._times[1], time.monotonic() - self._times[0])


def processor_time() -> float:
    """Processor time of this process and its finished children (the batch calls' workers), s."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system
