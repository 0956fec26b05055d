"""The design call's plumbing: independent tasks run in forked processes, and the progress
messages with the longest wait for one (:func:`impactdamper.studies.design.optimum.design_optima`)."""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from collections.abc import Callable

from impactdamper.analysis.parallel import map_tasks

__all__ = ["in_parallel", "Silences", "processor_time"]


def in_parallel(tasks: dict, workers: int) -> dict:
    """{key: task()} of independent tasks, ``workers`` at a time in forked processes
    (:func:`impactdamper.analysis.parallel.map_tasks`; in this one with a single worker), the
    answers in the tasks' order whatever ran where."""
    return dict(zip(tasks, map_tasks(lambda task: task(), list(tasks.values()), workers)))


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
