"""Independent pieces of work in forked processes, the result in the serial order: the one
place the package starts a process pool.

A study that does more per point than settle it (Algorithm No. 1's closed form beside the
batch, a pure-Python check of each point) splits its points with :func:`map_blocks`:
contiguous blocks, one per process, each computed exactly as the serial call would compute it,
so that the result does not depend on the number of workers. Pieces of very different cost (the
blocks of chains of :func:`impactdamper.analysis.batch.steady_states`, the two directions of a
sweep, the checks of a gap scan, the design call's tasks) go one by one to whichever process is
free (:func:`map_tasks`).
"""

from __future__ import annotations

import multiprocessing
import numbers
from collections.abc import Callable, Sequence

from impactdamper.core.arguments import ArgumentTypeError

__all__ = ["map_blocks", "map_tasks", "check_workers"]

# The work of the running map_blocks call, inherited by the forked workers (a closure need not
# be picklable that way); only its blocks' results travel back.
_JOB: tuple | None = None


def check_workers(workers) -> int:
    """``workers`` as an int >= 1, or a one-line error naming it."""
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 1:
        raise ArgumentTypeError(f"`workers` = {workers!r} is not allowed: must be an integer >= 1")
    return int(workers)


def _run_block(index: int) -> list:
    function, blocks = _JOB
    return list(function(blocks[index]))


def map_blocks(
    function: Callable[[list], Sequence], items: Sequence, workers: int = 1, min_block: int = 1, dynamic: bool = False
) -> list:
    """``function(block)`` over contiguous blocks of ``items``, concatenated in order.

    Parameters
    ----------
    function : callable
        ``function(list_of_items)`` -> one result per item, in order (a closure is fine).
    items : sequence
        The pieces of work, independent of each other.
    workers : int
        Processes (the 'fork' start method); 1, or fewer items than ``2 * min_block``: the
        serial call ``function(list(items))`` in this process.
    min_block : int
        Fewest items worth a process of their own.
    dynamic : bool
        Each item a block of its own, handed to whichever process is free (pieces of very
        different cost: no process left with the costly ones); the result in the same order.

    Returns
    -------
    list
        The results, as ``function(list(items))`` would give them.
    """
    global _JOB
    workers = check_workers(workers)
    items = list(items)
    blocks_count = min(workers, len(items) // max(int(min_block), 1))
    if blocks_count < 2 or "fork" not in multiprocessing.get_all_start_methods():
        return list(function(items))
    if dynamic:
        blocks = [[item] for item in items]
    else:
        cuts = [round(k * len(items) / blocks_count) for k in range(blocks_count + 1)]
        blocks = [items[a:b] for a, b in zip(cuts[:-1], cuts[1:])]
    _JOB = (function, blocks)
    try:
        with multiprocessing.get_context("fork").Pool(blocks_count) as pool:
            parts = pool.map(_run_block, range(len(blocks)), chunksize=1)
    finally:
        _JOB = None
    return [r for part in parts for r in part]


def map_tasks(function: Callable, items: Sequence, workers: int = 1) -> list:
    """``[function(item) for item in items]``, each item handed to whichever of ``workers``
    forked processes is free (:func:`map_blocks` with ``dynamic``; closures welcome)."""
    return map_blocks(lambda block: [function(item) for item in block], items, workers, dynamic=True)
