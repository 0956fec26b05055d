"""The upward and downward theta sweeps of many suppressors over their bands, in one batch call.

Step 1 of :func:`impactdamper.analysis.peaks.worst_branches`, and the rows of a frequency
response (:func:`impactdamper.analysis.response.frequency_response`), which reads its table off
the same sweeps: each band is swept upward and downward on its grid (:func:`band_grid`: steps of
at most ``step``, and the thetas a caller needs), each point from its neighbour's settled motion
(Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100: Algorithm No. 2 with the impact
law of eqs. 21-22, through :func:`impactdamper.steady_states`; independent chains, on
``workers`` processes, the serial result bit for bit). Each direction is swept once: the
locator and the response's table share the sweeps.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.linear_device import check_band
from impactdamper.analysis.peak_location import SweepPath, band_row, labels_of, settle_rows
from impactdamper.analysis.point import SweepPoint, SweepSettings
from impactdamper.core.parameters import Parameters, require_parameters
from impactdamper.core.validation import finite_argument

__all__ = [
    "BandSweeps",
    "band_sweeps",
    "band_grid",
    "band_points",
    "GRID_RTOL",
]

# A grid theta of the steps closer than this (relative) to a theta a caller gives is that theta:
# the caller's is kept as given (np.linspace of two grids lands one ulp apart at their common
# points), and the sweeps do not settle two points 1e-16 apart.
GRID_RTOL = 1e-9


def band_points(bands: Sequence[tuple[float, float]], step: float) -> int:
    """Grid points of the widest of ``bands``: steps of at most ``step``, ceil(width/step) + 1
    (at least 3). :func:`band_sweeps` gives each band its own (``band_points([band], step)``),
    so that a band's result does not depend on which other bands share the call."""
    width = max(b - a for a, b in bands)
    return max(int(math.ceil(width / step - 1e-9)) + 1, 3)


def band_grid(band: tuple[float, float], step: float, thetas: Sequence[float] = ()) -> np.ndarray:
    """The sweeps' grid of ``band``: ``band_points([band], step)`` equal steps and the
    ``thetas`` given (each inside the band, kept as given), in increasing order; a step's theta
    within :data:`GRID_RTOL` (relative) of a given one is dropped, equal thetas are one.

    Raises
    ------
    ValueError
        A given theta outside the band or not finite (named ``thetas``).
    """
    a, b = band
    given = np.asarray(thetas, float).ravel()
    if not np.all(np.isfinite(given)) or np.any(given < a) or np.any(given > b):
        raise ValueError(f"`thetas` = {given.tolist()!r} is not allowed: must be finite and inside the band {band}")
    steps = np.linspace(a, b, band_points([band], step))
    near = np.abs(steps[:, None] - given[None, :]) <= GRID_RTOL * np.abs(steps)[:, None]
    return np.unique(np.concatenate([steps[~near.any(axis=1)], given]))


@dataclass(frozen=True)
class BandSweeps:
    """Both sweeps of every case over its grid, from one batch call (:func:`band_sweeps`).

    Attributes
    ----------
    cases : tuple of Parameters
    bands : tuple of (float, float)
    grids : tuple of ndarray
        Each case's grid, increasing (:func:`band_grid`).
    settings : SweepSettings
    result : BatchResult
        The batch call's: chains of ``n`` points, case c's upward sweep chain 2 c (its first
        ``len(grids[c])`` points), its downward one chain 2 c + 1 (a shorter sweep is continued
        at its last theta and those points dropped: a point depends on its chain's earlier ones).
    n : int
        The chains' length (the longest grid's).
    paths : list of SweepPath
        Case by case, up then down, in the sweep's order.
    """

    cases: tuple = field(repr=False)
    bands: tuple
    grids: tuple = field(repr=False)
    settings: SweepSettings = field(repr=False)
    result: object = field(repr=False)
    n: int
    paths: list = field(repr=False)

    def rows(self, c: int, direction: str) -> np.ndarray:
        """The batch rows of case ``c``'s sweep ``direction`` (``up``, ``down``), in increasing theta."""
        m = len(self.grids[c])
        if direction == "up":
            return 2 * c * self.n + np.arange(m)
        return (2 * c + 1) * self.n + np.arange(m)[::-1]

    def points(self, c: int, thetas: Sequence[float]) -> dict[str, list[SweepPoint]]:
        """Case ``c``'s settled points at ``thetas`` (each on its grid, as given to
        :func:`band_grid`): ``{"up": [...], "down": [...]}`` in the order of ``thetas``."""
        grid, p = self.grids[c], self.cases[c]
        at = np.searchsorted(grid, np.asarray(thetas, float))
        if np.any(at >= len(grid)) or np.any(grid[np.minimum(at, len(grid) - 1)] != np.asarray(thetas, float)):
            raise ValueError(f"`thetas` = {list(thetas)!r} is not allowed: each must be a theta of the sweeps' grid")
        out = {}
        for d in ("up", "down"):
            rows = self.rows(c, d)[at]
            out[d] = [self.result.sweep_point(int(i), p.replace(theta=float(grid[j]))) for i, j in zip(rows, at)]
        return out


def _band(band: object) -> tuple[float, float]:
    """``band`` checked (:func:`check_band`), or a single theta (start = stop > 0)."""
    try:
        a, b = band  # type: ignore[misc]
        if float(a) == float(b) and finite_argument("theta_start", a) > 0:
            return float(a), float(b)
    except (TypeError, ValueError):
        pass
    return check_band(band)


def band_sweeps(
    cases: Sequence[Parameters],
    bands: Sequence[tuple[float, float]],
    *,
    step: float,
    thetas: Sequence[Sequence[float]] | None = None,
    settings: SweepSettings | None = None,
    workers: int = 1,
) -> BandSweeps:
    """Both sweeps of every case over its band in one batch call (module docstring).

    Parameters
    ----------
    cases : sequence of Parameters
        The suppressors (their theta is not used); the first one's scales are the batch's.
    bands : sequence of (float, float)
        Each one's band (one per case; a single theta where start = stop).
    step : float
        Largest theta step of each band's grid (:func:`band_grid`).
    thetas : sequence of sequences of float, optional
        Per case, the thetas its grid must hold (a frequency response's), inside its band.
    settings : SweepSettings, optional
    workers : int
        Processes of the batch call (the result is the same for any number).
    """
    cases = tuple(require_parameters(p, "cases") for p in cases)
    bands = tuple(_band(b) for b in bands)
    if len(bands) != len(cases):
        raise ValueError(f"`bands` is not allowed: {len(bands)} bands for {len(cases)} cases (one each)")
    thetas = [()] * len(cases) if thetas is None else list(thetas)
    if len(thetas) != len(cases):
        raise ValueError(f"`thetas` is not allowed: {len(thetas)} lists for {len(cases)} cases (one each)")
    step = finite_argument("step", step)
    if not step > 0:
        raise ValueError(f"`step` = {step!r} is not allowed: must be > 0")
    settings = settings or SweepSettings()
    grids = tuple(band_grid(band, step, t) for band, t in zip(bands, thetas))
    n = max((len(g) for g in grids), default=0)
    rows = []
    for p, th in zip(cases, grids):
        for t in (th, th[::-1]):
            rows += [band_row(p, x) for x in t] + [band_row(p, t[-1])] * (n - len(t))
    res = settle_rows(cases[0], rows, settings, n, workers=workers) if cases else None
    paths = []
    for c, th in enumerate(grids):
        for d, direction in enumerate(("up", "down")):
            sl = slice((2 * c + d) * n, (2 * c + d) * n + len(th))
            t = th if d == 0 else th[::-1]
            paths.append(
                SweepPath(c, direction, t, np.asarray(res.x1_max[sl], float), labels_of(res, sl), res.sections[sl])
            )
    return BandSweeps(cases, bands, grids, settings, res, n, paths)
