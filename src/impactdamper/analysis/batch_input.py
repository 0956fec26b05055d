"""The input of the many-point call (:func:`impactdamper.analysis.batch.steady_states`),
checked: the varied parameters' names, the points' values, the start states and the counts
(``chain_length``, ``workers``), each bad one refused in one line naming it (for a bad value:
its point and name); and the points turned into rows of relative parameters (:data:`COLUMNS`),
every value validated by :class:`~impactdamper.core.parameters.Parameters` as the reference's
single-point call validates it.
"""

from __future__ import annotations

import functools
import multiprocessing
import numbers
from collections.abc import Sequence

import numpy as np

from impactdamper.analysis.sweeps import PSEUDO_PARAMETERS, swept_names, with_value
from impactdamper.core.parameters import ArgumentTypeError, Parameters
from impactdamper.core.validation import show_value

__all__ = [
    "COLUMNS",
    "checked_names",
    "checked_values",
    "point_values",
    "checked_start_states",
    "checked_chain_length",
    "checked_workers",
]

# The relative parameters, in the columns of the rows handed to a backend.
COLUMNS = Parameters.names()


@functools.lru_cache(maxsize=4096)
def _changed_columns(base: Parameters, name: str, value: float) -> tuple:
    """((column index, value), ...) where ``with_value(base, name, value)`` differs from base;
    raises its named error for a bad value. Cached: a map's rows repeat the same values of
    their fast parameter, and constructing Parameters was a third of a cheap row's time."""
    q = with_value(base, name, value)
    return tuple((c, getattr(q, col)) for c, col in enumerate(COLUMNS) if getattr(q, col) != getattr(base, col))


def _refuse_masked(name: str, value) -> None:
    """A masked array is refused: its mask would be dropped silently (the masked entries read as
    whatever values they hide)."""
    if isinstance(value, np.ma.MaskedArray):
        raise ArgumentTypeError(
            f"`{name}` = {show_value(value)} is not allowed: a masked array (its mask would be dropped); "
            "pass the points to settle only, as a plain array"
        )


def checked_names(names) -> tuple:
    """The varied parameters: a sequence of known names, none given twice (``delta`` sets
    delta1 and delta2, so it goes with neither)."""
    if isinstance(names, str) or not isinstance(names, (Sequence, np.ndarray)):
        # A set maps the columns in hash order (theta and N swapped under PYTHONHASHSEED=1), a
        # generator was read by the check and came out empty: refused, in one line.
        raise ArgumentTypeError(
            f"`names` = {show_value(names)} is not allowed: must be an ordered sequence (a list or tuple) of "
            f"parameter names, one per column of `values`, not a {type(names).__name__}"
        )
    if not all(isinstance(n, str) for n in names):
        raise ArgumentTypeError(f"`names` = {show_value(names)} is not allowed: must be a sequence of parameter names")
    names = tuple(str(n) for n in names)
    if not names:
        raise ValueError("`names` = () is not allowed: must name at least one parameter")
    fields = {}
    for n in names:
        if n not in swept_names():
            raise ValueError(f"`names` = {names!r} is not allowed: {n!r} is not one of {', '.join(swept_names())}")
        for f in PSEUDO_PARAMETERS.get(n, (n,)):
            if f in fields:
                raise ValueError(
                    f"`names` = {names!r} is not allowed: {fields[f]!r} and {n!r} both set {f} (each parameter once)"
                )
            fields[f] = n
    return names


def checked_values(values, names: tuple) -> np.ndarray:
    """``values`` as a float array of shape (P, len(names)): one row per point, one real number
    per name (a bool, a string or a complex number is refused as Parameters refuses it; nothing
    is reshaped). The message names the point and the name."""
    allowed = f"must be finite real numbers of shape (P, {len(names)}): one row per point, one column per name {names}"
    _refuse_masked("values", values)
    if isinstance(values, np.ndarray) and values.dtype.kind in "iuf":
        arr = values
    else:
        try:
            arr = np.array(values, dtype=object)
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"`values` = {show_value(values)} is not allowed: {allowed}") from None
    if arr.ndim != 2 or arr.shape[1] != len(names):
        raise ValueError(f"`values` of shape {arr.shape} is not allowed: {allowed}")
    if arr.dtype == object:
        for (i, j), x in np.ndenumerate(arr):
            if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
                raise ArgumentTypeError(
                    f"`values` point {i}, `{names[j]}` = {show_value(x)} is not allowed: must be a real number"
                )
        try:
            arr = arr.astype(float)
        except OverflowError:
            raise ValueError(f"`values` is not allowed: {allowed} (an integer overflows a float)") from None
    arr = np.array(arr, dtype=float)
    bad = np.argwhere(~np.isfinite(arr))
    if len(bad):
        i, j = (int(x) for x in bad[0])
        raise ValueError(
            f"`values` point {i}, `{names[j]}` = {float(arr[i, j])!r} is not allowed: must be a finite number"
        )
    return arr


def point_values(base: Parameters, names: tuple, values: np.ndarray) -> np.ndarray:
    """(P, len(COLUMNS)) relative parameters, validated: every distinct value of each name goes
    through Parameters once (its named error, with the first point that has it)."""
    out = np.tile(np.array([getattr(base, c) for c in COLUMNS], float), (len(values), 1))
    for j, name in enumerate(names):
        for v in np.unique(values[:, j]):
            rows = values[:, j] == v
            try:
                changed = _changed_columns(base, name, float(v))
            except ValueError as err:  # (ArgumentTypeError too)
                raise ValueError(f"`values` point {int(np.argmax(rows))} ({name}): {err}") from None
            for c, x in changed:
                out[rows, c] = x
    return out


def checked_start_states(states, chain: bool, length: int, rows: np.ndarray, gap_tol: float) -> np.ndarray:
    """The batch's given start states, checked: finite with a non-negative gap (within the
    solver's ``gap_tol``) at the point each starts, shape (P, 4) (``chain`` False: one per
    point; ``chain`` True: one per chain of ``length`` points, put on the chain's first row and
    read there only), or shape (0, 4) when none are given. ``rows``: the points' parameters
    (point_values)."""
    if states is None:
        return np.zeros((0, 4))
    _refuse_masked("states", states)
    starts = np.arange(0, len(rows), length) if chain else np.arange(len(rows))
    what = "chain" if chain else "point"
    allowed = f"must be finite numbers of shape ({len(starts)}, 4), one start (x1, x2, x1', x2') per {what}"
    try:
        given = np.array(states, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"`states` is not allowed: {allowed}") from None
    if given.shape != (len(starts), 4) or not np.all(np.isfinite(given)):
        raise ValueError(f"`states` of shape {given.shape} is not allowed: {allowed}")
    delta0 = rows[starts, COLUMNS.index("gap")] * rows[starts, COLUMNS.index("x_st")]
    gap = delta0 - (given[:, 1] - given[:, 0])
    bad = np.flatnonzero(gap < -gap_tol * rows[starts, COLUMNS.index("x_st")])
    if len(bad):
        raise ValueError(
            f"`states` row {int(bad[0])} is not allowed: its gap Delta0 - (x2 - x1) = {gap[bad[0]]:.6g} m "
            "is negative (the bodies would overlap); allowed are states with x2 - x1 <= Delta0"
        )
    if not chain:
        return given
    out = np.zeros((len(rows), 4))
    out[starts] = given
    return out


def _checked_count(name: str, value, low: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < low:
        raise ArgumentTypeError(f"`{name}` = {show_value(value)} is not allowed: must be an integer >= {low}")
    return int(value)


def checked_chain_length(chain_length, chain: bool, P: int) -> int | None:
    """``chain_length``: None, or a count that cuts the ``P`` points of a chained call into
    whole chains."""
    if chain_length is None:
        return None
    chain_length = _checked_count("chain_length", chain_length)
    if not chain:
        raise ValueError("`chain_length` is not allowed with `chain=False`: the points are independent")
    if P % chain_length:
        raise ValueError(
            f"`chain_length` = {chain_length} is not allowed: the {P} points must form whole chains "
            "(P a multiple of chain_length)"
        )
    return chain_length


def checked_workers(workers) -> int:
    """``workers``: a count of processes, above 1 only where processes can be forked."""
    workers = _checked_count("workers", workers)
    if workers > 1 and "fork" not in multiprocessing.get_all_start_methods():
        raise ValueError(f"`workers` = {workers} is not allowed here: parallel points need the 'fork' start method")
    return workers
