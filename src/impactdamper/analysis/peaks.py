"""The worst branch of an impact suppressor over a band of forcing frequencies, located.

A designer cannot choose which motion the object settles on: as the forcing frequency theta =
omega/omega1 drifts slowly up or down, the motion follows a branch until it ends (a fold, a
grazing) and jumps to another. The peak a designer must expect is the largest max|x1|/x_st over
every branch such a slow sweep can follow, in either direction, and over the motions a
disturbance can put it on. :func:`worst_branches` finds it, for many suppressors at once
(Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100: Algorithm No. 2 with the impact law
of eqs. 21-22 settles every motion, through :func:`impactdamper.steady_states`):

1. **Sweeps.** Each suppressor's band is swept upward and downward on a grid of steps of at
   most ``step`` (and the thetas a caller adds, a frequency response's), each point from its
   neighbour's settled motion (one batch call for all suppressors,
   :func:`impactdamper.analysis.band_sweeps.band_sweeps`: independent chains, on ``workers``
   processes, the serial result bit for bit; sweeps a caller already ran are located on as
   they are).
2. **Candidates.** Along each sweep's path every local maximum of the samples and every change
   of motion is bracketed (:mod:`impactdamper.analysis.peak_location`).
3. **Location.** The largest brackets are shrunk by continuation to ``theta_tol`` wide (same
   module): a smooth maximum, or the end of a branch.
4. **No-contact floor.** Wherever the motion without contact exists (its relative amplitude
   below the gap) it is a stable steady state: its largest |x1|/x_st there, up to the first
   contact, is exact (:func:`impactdamper.analysis.linear_device.no_contact_floor`) and a lower
   bound of the worst branch.
5. **Random starts.** At the located peaks' frequencies, ``random_count`` random starts each
   (deterministic): an attractor no sweep follows counts if it is higher.

The worst branch is the largest of 3-5 (never below the largest grid sample); the band average
is the trapezoidal mean over the grid of the worst motion at each theta (the two sweeps and the
motion without contact where it exists). That peak is a conservative bound: a sample whose run
did not settle within its cap (``nonperiodic``) counts with its max|x1|, which may be a
transient's (far above resonance a random start decays by exp(-2 pi delta1 / theta) a period,
0.9984 at theta 200, and its unsettled end read 75.8 x_st where every settled motion is 3e-5 to
1e-4). :attr:`WorstBranch.settled_peak` is the settled motions' alone, and
:attr:`WorstBranch.unsettled` lists the samples left out of it. (A search that ranks devices
keeps the bound: ranked by their settled peaks alone, the design search picked a device whose
unsettled samples rose above its settled peak.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from collections.abc import Sequence

import numpy as np

from impactdamper.analysis.band_sweeps import BandSweeps, band_points, band_sweeps
from impactdamper.analysis.linear_device import NoContactFloor, check_band, no_contact_floor
from impactdamper.analysis.peak_location import (
    CANDIDATES,
    FAILED_CODE,
    NAMES,
    BranchPeak,
    SweepPath,
    band_row,
    labels_of,
    locate_peaks,
    settle_rows,
)
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.sweeps import random_initial_state
from impactdamper.core.parameters import Parameters, require_parameters
from impactdamper.core.steady import REGIMES
from impactdamper.core.validation import finite_argument, integer_argument

__all__ = [
    "WorstBranch",
    "worst_branches",
    "worst_branch",
    "band_points",
    "STEP",
    "THETA_TOL",
    "SEARCH_THETA_TOL",
    "CANDIDATES",
    "RANDOM_COUNT",
    "RANDOM_THETAS",
]

# Largest theta step of the sweeps' grid: a resonance peak of the suppressors studied is
# >= 0.05 wide in theta, so 0.02 puts >= 2 samples on it, enough to bracket it (the location
# does the rest; a slow test compares with sweeps of step 0.002).
STEP = 0.02
# A located peak's final bracket is at most this wide in theta ...
THETA_TOL = 1e-6
# ... and inside an optimiser's search (the answer it returns is located again to THETA_TOL).
SEARCH_THETA_TOL = 1e-3
# Random starts per located peak's theta, at the RANDOM_THETAS highest located peaks.
RANDOM_COUNT = 3
RANDOM_THETAS = 2
# Peaks whose values differ by less than this (relative) tie: the same maximum reached along
# several paths (a sweep's located maximum, the closed form without contact, a random start at
# its theta agree to ~1e-15), or two equal maxima (a TMD's equal peaks, 2e-10 apart). Which of
# them names the worst branch must not rest on the last bits: the tie at the smallest theta
# (peaks within DISTINCT_THETA of it are one), and there the first source in SOURCE_ORDER (the
# closed form's theta is exact, a located one within THETA_TOL). The located values' own
# accuracy (~1e-12 at a smooth maximum located to THETA_TOL) is far below TIE_RTOL.
TIE_RTOL = 1e-9
DISTINCT_THETA = 1e-3
SOURCE_ORDER = ("no contact", "up", "down", "random")
NONPERIODIC_CODE = REGIMES.index("nonperiodic")


@dataclass(frozen=True)
class WorstBranch:
    """The worst branch of one suppressor over a band (see :func:`worst_branches`).

    Attributes
    ----------
    p : Parameters
    band : (float, float)
    thetas : ndarray, shape (n,)
        The sweeps' grid.
    up, down : ndarray, shape (n,)
        max|x1|/x_st of the upward and downward sweep at each grid theta (nan: failed).
    up_k, down_k : ndarray of int
        Period multiples (0: nonperiodic or failed).
    up_sections, down_sections : ndarray, shape (n, 4)
        Settled section states, for the cycles' loads.
    up_impacts, down_impacts : ndarray, shape (n,)
        Impacts per forcing period z/k (nan where the motion did not settle).
    up_velocity, down_velocity : ndarray, shape (n,)
        The largest closing velocity of the cycle's first impacts (the batch keeps 16), over
        x_st omega (0 without impacts).
    peaks : tuple of BranchPeak
        Located maxima of the sweeps, the floor and the random starts, largest first.
    floor : NoContactFloor
    failed : int
        Grid points whose run reached the solver's work bound.
    unsettled : tuple of dict
        The grid samples and random starts that did not settle (nonperiodic): ``theta``,
        ``source``, ``periods`` (forcing periods run), ``max_abs_x1`` (of the run's last window,
        possibly a transient's).
    """

    p: Parameters = field(repr=False)
    band: tuple
    thetas: np.ndarray = field(repr=False)
    up: np.ndarray = field(repr=False)
    down: np.ndarray = field(repr=False)
    up_k: np.ndarray = field(repr=False)
    down_k: np.ndarray = field(repr=False)
    up_sections: np.ndarray = field(repr=False)
    down_sections: np.ndarray = field(repr=False)
    up_impacts: np.ndarray = field(repr=False)
    down_impacts: np.ndarray = field(repr=False)
    up_velocity: np.ndarray = field(repr=False)
    down_velocity: np.ndarray = field(repr=False)
    peaks: tuple
    floor: NoContactFloor = field(repr=False)
    failed: int = 0
    unsettled: tuple = ()

    @property
    def worst_sample(self) -> np.ndarray:
        """The worst motion at each grid theta: the two sweeps and, where it exists, the
        motion without contact (closed form). Shape (n,)."""
        linear = np.where(self.floor.admissible(self.thetas), _linear_amplitude(self.p, self.thetas), np.nan)
        return np.fmax(np.fmax(self.up, self.down), linear)

    @property
    def grid_peak(self) -> float:
        """The largest grid sample of the two sweeps."""
        return float(np.nanmax(np.fmax(self.up, self.down)))

    @property
    def top(self) -> BranchPeak:
        """The worst branch's peak: the largest of :attr:`peaks`, or among those within
        :data:`TIE_RTOL` of it the one at the smallest theta (:data:`DISTINCT_THETA`), from the
        first source in :data:`SOURCE_ORDER` there."""
        best = self.peaks[0]
        if not np.isfinite(best.value):
            return best
        tied = [q for q in self.peaks if q.value >= best.value - TIE_RTOL * abs(best.value)]
        lowest = min(q.theta for q in tied)
        rank = {name: i for i, name in enumerate(SOURCE_ORDER)}
        return min(
            (q for q in tied if q.theta <= lowest + DISTINCT_THETA),
            key=lambda q: (rank.get(q.source, len(rank)), q.theta),
        )

    @property
    def peak(self) -> float:
        """The worst branch's max|x1|/x_st (never below the largest grid sample)."""
        return max(self.peaks[0].value, self.grid_peak)

    @property
    def peak_theta(self) -> float:
        return self.top.theta

    @property
    def settled(self) -> BranchPeak | None:
        """The largest peak of a settled motion (located, the floor, a settled random start, or a
        settled grid sample), or None if nothing settled over the band."""
        out = next((q for q in self.peaks if q.label not in ("np", "failed") and np.isfinite(q.value)), None)
        for direction, y, k in (("up", self.up, self.up_k), ("down", self.down, self.down_k)):
            y = np.where(k > 0, y, np.nan)
            if np.any(np.isfinite(y)) and (out is None or np.nanmax(y) > out.value):
                i = int(np.nanargmax(y))
                out = BranchPeak(float(self.thetas[i]), float(y[i]), direction, "settled", "sample")
        return out

    @property
    def settled_peak(self) -> float:
        """max|x1|/x_st of :attr:`settled` (nan if nothing settled)."""
        return math.nan if self.settled is None else self.settled.value

    @property
    def band_average(self) -> float:
        """Trapezoidal mean over the grid of :attr:`worst_sample`."""
        x, y = self.thetas, self.worst_sample
        return float(np.trapezoid(y, x) / (x[-1] - x[0]))

    def branch(self) -> str:
        """The worst branch in words: ``up, 1/1, branch end`` and the like."""
        t = self.top
        return f"{t.source}, {t.label}, {t.kind}"

    def to_dict(self) -> dict:
        return {
            "peak": self.peak,
            "peak_theta": self.peak_theta,
            "peak_branch": self.branch(),
            "grid_peak": self.grid_peak,
            "band_average": self.band_average,
            "no_contact_floor": self.floor.value,
            "no_contact_floor_theta": self.floor.theta,
            "peaks": [q.to_dict() for q in self.peaks],
            "failed": self.failed,
            "settled_peak": self.settled_peak,
            "unsettled": len(self.unsettled),
        }


def _linear_amplitude(p: Parameters, thetas: np.ndarray) -> np.ndarray:
    from impactdamper.analysis.linear_device import LinearDevice

    return LinearDevice.of(p).amplitude(thetas)


def _unsettled(res, rows, source: str) -> list[dict]:
    """The points ``rows`` (indices) of a batch result that did not settle (nonperiodic)."""
    return [
        {
            "theta": float(res.values[i, 0]),
            "source": source,
            "periods": int(res.periods[i]),
            "max_abs_x1": float(res.x1_max[i]),
        }
        for i in rows
        if res.regime_code[i] == NONPERIODIC_CODE
    ]


def _key(p: Parameters) -> list[int]:
    """The suppressor's relative parameters as integers (their bits): its random starts' seed,
    so that they do not depend on which other suppressors share the call."""
    return [int(x) for x in np.array([getattr(p, n) for n in NAMES], float).view(np.uint64)]


def _random_peaks(base, cases, tops: list[list[float]], settings, count: int, seed: int, workers: int) -> list:
    """The largest attractor from ``count`` random starts at each theta of ``tops[c]`` (per
    case): a BranchPeak per case, or None."""
    rows, states, owner = [], [], []
    for c, (p, thetas) in enumerate(zip(cases, tops)):
        for i, t in enumerate(thetas):
            q = p.replace(theta=float(t))
            for j in range(count):
                rows.append(band_row(p, t))
                states.append(random_initial_state(q, np.random.default_rng([int(seed), *_key(p), i, j])))
                owner.append(c)
    out, lost = [None] * len(cases), [[] for _ in cases]
    if not rows:
        return out, lost
    res = settle_rows(base, rows, settings, 1, np.array(states), workers, chain=False)
    labs = labels_of(res, slice(None))
    for r, c in enumerate(owner):
        lost[c] += _unsettled(res, [r], "random")
        y = float(res.x1_max[r])
        if np.isfinite(y) and (out[c] is None or y > out[c].value):
            out[c] = BranchPeak(float(res.values[r, 0]), y, "random", labs[r], "sample")
    return out, lost


def _impacts(res, sl: slice) -> tuple[np.ndarray, np.ndarray]:
    """(impacts per period z/k, the largest closing velocity of the first impacts) of the points
    ``sl`` of a batch result (nan where the motion did not settle; 0 without impacts)."""
    k = res.period_multiple[sl].astype(float)
    z = res.impacts_per_cycle[sl].astype(float)
    per = np.where(k > 0, z / np.where(k > 0, k, 1.0), np.nan)
    v = np.abs(res.velocities[sl])
    top = np.where(np.all(np.isnan(v), axis=1), 0.0, np.nanmax(np.where(np.isnan(v), -np.inf, v), axis=1))
    return per, top


def worst_branches(
    cases: Sequence[Parameters],
    bands: Sequence[tuple[float, float]],
    *,
    step: float = STEP,
    theta_tol: float = THETA_TOL,
    candidates: int = CANDIDATES,
    random_count: int = RANDOM_COUNT,
    settings: SweepSettings | None = None,
    workers: int = 1,
    seed: int = 0,
    thetas: Sequence[Sequence[float]] | None = None,
    sweeps: BandSweeps | None = None,
) -> list[WorstBranch]:
    """The worst branch of each suppressor over its band, located (module docstring).

    Parameters
    ----------
    cases : sequence of Parameters
        The suppressors (their theta is not used).
    bands : sequence of (float, float)
        Each one's band (one per case).
    step : float
        Largest theta step of the sweeps' grid (each band its own number of points,
        :func:`band_points`; a band's result does not depend on the other bands of the call).
    theta_tol : float
        Width of a located peak's final bracket.
    candidates : int
        Brackets located per sweep path at most.
    random_count : int
        Random starts at each of the RANDOM_THETAS highest located peaks (0: none).
    settings : SweepSettings, optional
        How each point settles.
    workers : int
        Processes of the batch calls (the result is the same for any number).
    seed : int
        Of the random starts.
    thetas : sequence of sequences of float, optional
        Per case, further thetas of its sweeps' grid (a frequency response's:
        :func:`~impactdamper.analysis.band_sweeps.band_grid`).
    sweeps : BandSweeps, optional
        The sweeps of these cases and bands already run
        (:func:`~impactdamper.analysis.band_sweeps.band_sweeps` with this ``step``, ``thetas``
        and ``settings``): located on, not swept again.

    Returns
    -------
    list of WorstBranch
        One per case, in order.
    """
    cases, bands, step, theta_tol = _checked(cases, bands, step, theta_tol)
    candidates = integer_argument("candidates", candidates, 1, 100)
    random_count = integer_argument("random_count", random_count, 0, 100)
    settings = settings or SweepSettings()
    if not cases:
        return []
    if sweeps is None:
        sweeps = band_sweeps(cases, bands, step=step, thetas=thetas, settings=settings, workers=workers)
    elif sweeps.cases != tuple(cases) or sweeps.bands != tuple(bands) or sweeps.settings != settings:
        raise ValueError("`sweeps` is not allowed: must be the sweeps of these cases and bands, with these settings")
    base, res, paths = cases[0], sweeps.result, sweeps.paths
    floors = [no_contact_floor(p, band) for p, band in zip(cases, bands)]
    located = locate_peaks(base, cases, paths, [f.value for f in floors], candidates, settings, theta_tol, workers)
    tops = [_distinct_thetas(peaks, RANDOM_THETAS) if random_count else [] for peaks in located]
    randoms, lost = _random_peaks(base, cases, tops, settings, random_count, seed, workers)
    out = []
    for c, (p, band) in enumerate(zip(cases, bands)):
        peaks = list(located[c])
        fl = floors[c]
        if fl.value > 0:
            kind = "first contact" if fl.first_contact else "maximum"
            peaks.append(BranchPeak(fl.theta, fl.value, "no contact", "0/1", kind))
        if randoms[c] is not None:
            peaks.append(randoms[c])
        if not any(np.isfinite(q.value) for q in peaks):
            raise ValueError(f"`cases` item {c} is not allowed: no motion settled over its band {band}")
        out.append(_worst(p, band, res, paths[2 * c], paths[2 * c + 1], c, sweeps.n, tuple(peaks), fl, lost[c]))
    return out


def _checked(cases, bands, step, theta_tol) -> tuple:
    """(cases, bands, step, theta_tol) of :func:`worst_branches` checked (one-line errors)."""
    cases = [require_parameters(p, "cases") for p in cases]
    bands = [check_band(b) for b in bands]
    if len(bands) != len(cases):
        raise ValueError(f"`bands` is not allowed: {len(bands)} bands for {len(cases)} cases (one each)")
    step, theta_tol = finite_argument("step", step), finite_argument("theta_tol", theta_tol)
    if not step > 0 or not theta_tol > 0:
        raise ValueError(f"`step` = {step!r}, `theta_tol` = {theta_tol!r} are not allowed: both must be > 0")
    return cases, bands, step, theta_tol


def _distinct_thetas(peaks: list, count: int) -> list[float]:
    """The thetas of the ``count`` highest of ``peaks``, each more than DISTINCT_THETA from the others."""
    out = []
    for q in sorted(peaks, key=lambda q: -q.value):
        if all(abs(q.theta - t) > DISTINCT_THETA for t in out):
            out.append(q.theta)
    return out[:count]


def _worst(
    p, band, res, up: SweepPath, down: SweepPath, c: int, n: int, peaks: tuple, fl, randoms: list
) -> WorstBranch:
    """Case ``c``'s WorstBranch from its sweeps (the first len(up.t) points of chains 2 c and
    2 c + 1 of ``res``, chains of n points)."""
    m = len(up.t)
    sl_up, sl_down = slice(2 * c * n, 2 * c * n + m), slice((2 * c + 1) * n, (2 * c + 1) * n + m)
    (up_z, up_v), (down_z, down_v) = _impacts(res, sl_up), _impacts(res, sl_down)
    failed = int(np.sum(res.regime_code[sl_up] == FAILED_CODE) + np.sum(res.regime_code[sl_down] == FAILED_CODE))
    rows = np.arange(len(res.values))
    unsettled = _unsettled(res, rows[sl_up], "up") + _unsettled(res, rows[sl_down], "down") + randoms
    return WorstBranch(
        p=p,
        band=band,
        thetas=up.t,
        up=up.y,
        down=down.y[::-1].copy(),
        up_k=res.period_multiple[sl_up].copy(),
        down_k=res.period_multiple[sl_down][::-1].copy(),
        up_sections=up.sections.copy(),
        down_sections=down.sections[::-1].copy(),
        up_impacts=up_z,
        down_impacts=down_z[::-1],
        up_velocity=up_v,
        down_velocity=down_v[::-1],
        peaks=tuple(sorted(peaks, key=lambda q: -q.value)),
        floor=fl,
        failed=failed,
        unsettled=tuple(unsettled),
    )


def worst_branch(
    p: Parameters, band: tuple[float, float] = (0.5, 1.5), *, thetas: Sequence[float] | None = None, **options
) -> WorstBranch:
    """The worst branch of one suppressor over ``band`` (:func:`worst_branches`' options;
    ``thetas``: this one's further grid thetas, ``sweeps``: of ``[p]`` and ``[band]``)."""
    return worst_branches([p], [band], thetas=None if thetas is None else [thetas], **options)[0]
