"""The compass (pattern) search's poll loop, once: the design search's lockstep starts
(:mod:`impactdamper.studies.design.search`) and the claims' nearest robust point
(:mod:`impactdamper.studies.claims.nearest`) differ only in the moves they poll and in how a poll
judges them (an objective to lower, or a feasibility test to keep), both given as arguments.

Each poll offers every active point its moves of step h; the judge picks one per point or none.
A point that moved keeps its step and remembers the displacement (the pattern move a caller may
repeat); one that did not halves its step, and stays active while the step is at least ``floor``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["compass"]


def compass(
    starts: np.ndarray,
    step: float,
    floor: float,
    moves: Callable[[np.ndarray, float, np.ndarray], list],
    judge: Callable[[np.ndarray, np.ndarray, np.ndarray, list], list],
    max_polls: int,
    *,
    after_poll: Callable[[int, np.ndarray], None] | None = None,
) -> tuple[np.ndarray, int]:
    """Compass searches from ``starts`` (shape (s, d)) in lockstep.

    Parameters
    ----------
    starts : ndarray, shape (s, d)
    step, floor : float
        The first step, and the smallest one polled.
    moves : callable(u, h, last) -> list of ndarray
        A point's moves of step ``h``; ``last`` is its last successful displacement (zeros after
        a failed poll or at the start).
    judge : callable(idx, u, h, candidates) -> list
        For the active points ``idx`` (their points ``u``, shape (len(idx), d), and steps ``h``)
        and each one's list of moves, the chosen move's index per point, or None (the poll failed there).
    max_polls : int
    after_poll : callable(poll, h), optional
        Called after each poll with its number (from 1) and the steps.

    Returns
    -------
    u : ndarray, shape (s, d)
        The points reached.
    polls : int
        The polls made.
    """
    u = np.array(starts, float)
    h = np.full(len(u), float(step))
    last = np.zeros_like(u)
    active = h >= floor
    polls = 0
    while polls < int(max_polls) and active.any():
        polls += 1
        idx = np.flatnonzero(active)
        candidates = [moves(u[i], h[i], last[i]) for i in idx]
        for i, cands, k in zip(idx, candidates, judge(idx, u[idx], h[idx], candidates)):
            if k is None:
                last[i] = 0.0
                h[i] *= 0.5
                active[i] = h[i] >= floor
            else:
                last[i] = cands[k] - u[i]
                u[i] = cands[k]
        if after_poll is not None:
            after_poll(polls, h)
    return u, polls
