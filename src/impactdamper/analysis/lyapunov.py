"""Lyapunov exponents of the impacting flow: the spectrum of a motion, its errors and its label.

The motion of the suppressor of Timofeev et al. (2019) is piecewise linear, and a perturbation
of its state y = (x1, x2, x1', x2') is carried exactly by the flow's transition matrices
between events and the saltation matrices of the impacts (eqs. 21-22; det = R^2), captures
into persistent contact and lift-offs (Muller 1995): :mod:`impactdamper.core.tangent` holds
these pieces and the reference's walk, which a backend runs (the ``lyapunov`` operation of
:mod:`impactdamper.core.backends`; the compiled backend's kernel walks its own event loop).
The walk re-orthonormalises its frame after every event and at every forcing period (QR,
Benettin et al. 1980) and returns each period's growths log |R_ii|; this module turns them
into exponents with errors and a label.

The forcing makes the flow non-autonomous: a perturbation along the orbit is not a solution
(the forcing's phase is fixed), so there is no trivial zero exponent, and at a stable periodic
orbit of period k T all four exponents are log|mu_i| / k per forcing period, mu_i its Floquet
multipliers. Once a motion is captured into persistent contact the two exponents transverse
to the constraint are -inf.

Averages. The per-period increments of log |R_ii| are averaged with the smooth weight
w(s) = exp(-1/(s (1 - s))), s in (0, 1) across the averaged periods (the weighted Birkhoff
average of Das & Yorke 2017). On a periodic or quasi-periodic motion the increments are a
smooth function of a rotation (a complex pair of multipliers turns the frame within its
plane), and the weighted average converges faster than any power of the run's length, where
the plain average converges like 1/length (at the stated case, 2000 periods, against the
Floquet multipliers: 4e-12 against 3e-4); on a chaotic motion both converge like
1/sqrt(length). The exponent is the weighted average over all the averaged periods; its error
is the standard error of the same weighted average over each of ``blocks`` blocks (a fair
estimate for a chaotic motion, whose blocks are nearly independent; an overestimate for a
regular one, whose blocks are shorter than the run).

Labels (:func:`classify_spectrum`, thresholds :data:`SIGNIFICANCE` and :data:`ZERO_BAND`):
chaotic, chaotic transient, quasi-periodic, periodic, not settled. Every label is a statement
about the finite window the run averaged (its ``transient + warmup`` periods skipped, then
``periods``): "chaotic" is claimed only where the largest exponent is positive in both halves
of that window, the halves agree within their errors, and the motion has not settled onto a
cycle by the window's end (:func:`settled_end`); a positive exponent whose motion settled
before the end is a "chaotic transient" (at gap -10.6 with the defaults: positive, +0.18 a
period, over a run that lands on a 7 T cycle in its last block).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
import numpy as np

from impactdamper.core.backends import get_backend
from impactdamper.core.parameters import Parameters, ScaleMap, require_parameters, state_scale
from impactdamper.core.steady import start_in_first_period
from impactdamper.core.tangent import TangentRun
from impactdamper.core.validation import (
    Tolerances,
    check_start_state,
    check_tolerances,
    finite_argument,
    integer_argument,
)

__all__ = [
    "LyapunovSpectrum",
    "lyapunov_spectrum",
    "spectrum_from_section",
    "classify_spectrum",
    "birkhoff_weights",
    "LABELS",
    "SIGNIFICANCE",
    "SETTLE_SPAN",
    "SETTLE_TOL",
    "MAX_SETTLED_PERIOD",
    "ZERO_BAND",
    "DEFAULT_PERIODS",
    "DEFAULT_TRANSIENT",
    "DEFAULT_WARMUP",
    "DEFAULT_BLOCKS",
]

# --- run lengths (forcing periods) ------------------------------------------------------
# Periods of motion discarded before the tangent product starts: the reference case's slowest
# stable mode decays by e^-0.34 a period, so 500 periods bring a motion from the paper's step 1
# onto its attractor to rounding (e^-170); near a bifurcation, pass more.
DEFAULT_TRANSIENT = 500
# Periods of tangent product discarded while the orthonormal frame turns onto the Lyapunov
# vectors: its misalignment decays like e^{-(lambda_i - lambda_{i+1}) n}, and the smallest gap
# between distinct exponents at the test orbits is 0.056 a period (gap +14), so 200 periods
# leave < 2e-5, which the averaging weight (vanishing at the ends of the run) suppresses further.
DEFAULT_WARMUP = 200
# Periods averaged, and the blocks they are split into for the error estimate (10 blocks of
# 200: the standard error of a mean of 10 is itself known to ~25 %).
DEFAULT_PERIODS = 2000
DEFAULT_BLOCKS = 10
# Bounds on the work of one call (the pure-Python walk advances ~2000-6000 periods a second,
# the compiled one 50-100 times more).
MAX_PERIODS = 1_000_000

# --- labels -----------------------------------------------------------------------------
LABELS = ("chaotic", "chaotic transient", "quasi-periodic", "periodic", "not settled")
# "Beyond its error" means more than SIGNIFICANCE standard errors of the block mean: with 10
# blocks (9 degrees of freedom, Student's t) a one-sided 3-sigma excursion happens by chance
# with probability ~0.7 %.
SIGNIFICANCE = 3.0
# Exponents (per forcing period) within ZERO_BAND of zero are not told from zero: a
# perturbation growing at 1e-3 a period changes by a factor e^2 over the default 2000 periods,
# too little to separate a weakly chaotic motion from a torus or a slowly decaying transient.
# It also holds the torus's estimates (gap -10.2: exponent 2.5e-8, block standard error 3e-5).
ZERO_BAND = 1e-3
# A run has settled by its end when its last SETTLE_SPAN sections repeat with one period k T,
# k <= MAX_SETTLED_PERIOD, to SETTLE_TOL (relative to x_st and x_st omega). A chaotic motion
# (largest exponent >= ZERO_BAND) shadows a k T cycle to 1e-4 for 20 periods only from within
# ~1e-4 e^{-20 lambda} of it; a stable cycle reached in the window is inside 1e-4 for good (at
# gap -10.6, the 7 T cycle its default run lands on: 3e-6 over its last 50 sections).
SETTLE_SPAN = 20
SETTLE_TOL = 1e-4
MAX_SETTLED_PERIOD = 12


def birkhoff_weights(n: int) -> np.ndarray:
    """Weights of the weighted Birkhoff average over n samples, shape (n,), summing to 1:
    w(s) = exp(-1/(s (1 - s))) at s = (i + 1/2)/n (Das & Yorke 2017)."""
    s = (np.arange(n) + 0.5) / n
    w = np.exp(-1.0 / (s * (1.0 - s)))
    return w / w.sum()


@dataclass(frozen=True)
class LyapunovSpectrum:
    """The Lyapunov spectrum of a motion, per forcing period.

    Attributes
    ----------
    p : Parameters
    exponents : ndarray, shape (4,)
        Lyapunov exponents of (x1, x2, x1', x2') per forcing period T (lambda T, comparable
        with log|mu| / k at a periodic orbit of period k T), largest first; ``-inf`` for the
        directions a capture into persistent contact annihilates. The report uses these.
    errors : ndarray, shape (4,)
        Standard error of each: the standard deviation of the block averages over
        sqrt(blocks) (nan for -inf exponents; see the module docstring).
    spreads : ndarray, shape (4,)
        Largest minus smallest block average (nan for -inf exponents).
    block_averages : ndarray, shape (blocks, 4)
        Weighted average of the per-period increments over each block.
    increments : ndarray, shape (periods, 4)
        log |R_ii| summed over each averaged period (the finite-time exponents of each period).
    sections : ndarray, shape (periods, 4)
        The state (x1, x2, x1', x2') at the start of each averaged period, at times
        ``t_section`` + n T (the forcing's phase is the same at each).
    t_section : float
        Forcing phase time of the sections, s, in [0, T).
    dimension : int
        Dimension of the tangent space at the end (4, or 2 once the motion was captured).
    periods, transient, warmup, blocks : int
        Periods averaged; periods of motion discarded; periods of tangent product discarded;
        blocks of the error estimate.
    impacts, captures, liftoffs, grazing : int
        Events in the averaged periods (``grazing``: impacts slower than ``GRAZING_VELOCITY``
        x_st omega).
    contact_time : float
        Share of the averaged time spent in persistent contact.
    method : str
    backend : str
        Who walked the tangent (``compiled``, ``python``).
    fallback : str
        Why the reference walked where the compiled backend was asked ("" otherwise: see
        :mod:`impactdamper.analysis.solve`).
    """

    p: Parameters = field(repr=False)
    exponents: np.ndarray
    errors: np.ndarray
    spreads: np.ndarray
    block_averages: np.ndarray = field(repr=False)
    increments: np.ndarray = field(repr=False)
    sections: np.ndarray = field(repr=False)
    t_section: float
    dimension: int
    periods: int
    transient: int
    warmup: int
    blocks: int
    impacts: int
    captures: int
    liftoffs: int
    grazing: int
    contact_time: float
    method: str = "tangent map: exact flows, saltation matrices, QR per event and period"
    backend: str = "python"
    fallback: str = ""

    @property
    def exponents_per_second(self) -> np.ndarray:
        """The exponents in 1/s (lambda = exponents / T), shape (4,)."""
        return self.exponents / self.p.T

    @property
    def label(self) -> str:
        """:func:`classify_spectrum` of this spectrum."""
        return classify_spectrum(self)

    @property
    def halves(self) -> tuple[np.ndarray, np.ndarray]:
        """The largest exponent over each half of the averaged window: (estimates, errors),
        each shape (2,): the mean of the first ``blocks // 2`` block averages and of the rest,
        and their standard errors from the blocks' spread within the halves, pooled (nan with
        fewer than 4 blocks, or for a -inf exponent)."""
        h = self.blocks // 2
        parts = (self.block_averages[:h, 0], self.block_averages[h:, 0])
        est = np.array([part.mean() for part in parts])
        err = np.full(2, math.nan)
        if self.blocks >= 4 and np.isfinite(est).all():
            pooled = sum(((part - part.mean()) ** 2).sum() for part in parts) / (self.blocks - 2)
            err = np.sqrt(pooled / np.array([len(part) for part in parts]))
        return est, err

    @property
    def settled(self) -> tuple[int, int] | None:
        """:func:`settled_end` of the averaged sections: (k, first period of the settled
        stretch counted from the run's start), or None."""
        found = _settled_end(self.sections / state_scale(self.p))
        if found is None:
            return None
        return found[0], self.transient + self.warmup + found[1]

    def to_dict(self) -> dict:
        """A JSON-ready summary (exponents per period and per second, errors, counts, label)."""

        def listed(a):
            return [None if not math.isfinite(v) else float(v) for v in a]

        halves, half_errors = self.halves
        settled = self.settled
        return {
            "exponents": listed(self.exponents),
            "exponents_per_second": listed(self.exponents_per_second),
            "errors": listed(self.errors),
            "spreads": listed(self.spreads),
            "label": self.label,
            "halves": listed(halves),
            "half_errors": listed(half_errors),
            "settled_period": None if settled is None else settled[0],
            "settled_since": None if settled is None else settled[1],
            "window": [self.transient + self.warmup, self.transient + self.warmup + self.periods],
            "significance": SIGNIFICANCE,
            "zero_band": ZERO_BAND,
            "dimension": self.dimension,
            "periods": self.periods,
            "transient": self.transient,
            "warmup": self.warmup,
            "blocks": self.blocks,
            "impacts": self.impacts,
            "captures": self.captures,
            "liftoffs": self.liftoffs,
            "grazing": self.grazing,
            "contact_time": self.contact_time,
            "method": self.method,
            "backend": self.backend,
            "fallback": self.fallback,
            "parameters": self.p.to_dict(),
        }


def _settled_end(sections: np.ndarray) -> tuple[int, int] | None:
    """Whether a run's sections (shape (n, 4), in relative units) have settled by their end onto
    a cycle of period k T, k <= :data:`MAX_SETTLED_PERIOD`: the smallest k for which the last
    :data:`SETTLE_SPAN` sections repeat after k periods to :data:`SETTLE_TOL`, and the index of
    the first section of the longest such stretch ending at the run's end; None if none."""
    y = np.asarray(sections, float)
    n = len(y)
    for k in range(1, MAX_SETTLED_PERIOD + 1):
        if n < SETTLE_SPAN + k:
            return None
        close = np.abs(y[k:] - y[:-k]).max(axis=1) <= SETTLE_TOL
        if close[-SETTLE_SPAN:].all():
            misses = np.flatnonzero(~close)
            return k, int(misses[-1] + 1) if len(misses) else 0
    return None


def classify_spectrum(s: LyapunovSpectrum) -> str:
    """What a motion is over the run's averaged window, from its spectrum: one of :data:`LABELS`.

    * ``chaotic``: the largest exponent is positive beyond its error (more than
      ``SIGNIFICANCE`` standard errors) and beyond ``ZERO_BAND``, over the window and over each
      of its halves (:attr:`LyapunovSpectrum.halves`), the halves agree within ``SIGNIFICANCE``
      combined errors, and the motion has not settled onto a cycle by the window's end
      (:func:`settled_end`): a finite-window statement, a chaotic attractor or a chaotic
      transient longer than the run;
    * ``chaotic transient``: the largest exponent is positive over the window, but the motion
      has settled onto a cycle before its end (:attr:`LyapunovSpectrum.settled`);
    * ``periodic``: the largest exponent (hence all) is negative in the same sense: every
      perturbation decays (the stroboscopic map has no neutral direction, there being no
      trivial zero exponent for the forced, non-autonomous flow); or, the largest exponent not
      positive, the motion has settled onto a cycle before the window's end (a late settling
      whose transient keeps the window's average from resolving below zero);
    * ``quasi-periodic``: the largest exponent is resolved to be zero (its interval of
      ``SIGNIFICANCE`` standard errors lies inside +-``ZERO_BAND``) and the next is negative
      beyond its error: one neutral direction, along an invariant torus;
    * ``not settled``: none of these resolved within the run (among them a positive exponent
      whose halves disagree or are not each positive beyond their errors).
    """
    lam, err = s.exponents, s.errors

    def positive(x: float, e: float) -> bool:
        return bool(x - SIGNIFICANCE * e > 0.0 and x > ZERO_BAND)

    def negative(i: int) -> bool:
        return bool(lam[i] == -math.inf or (lam[i] + SIGNIFICANCE * err[i] < 0.0 and lam[i] < -ZERO_BAND))

    if positive(lam[0], err[0]):
        if s.settled is not None:
            return "chaotic transient"
        (a, b), (ea, eb) = s.halves
        agree = abs(a - b) <= SIGNIFICANCE * math.hypot(ea, eb)
        return "chaotic" if positive(a, ea) and positive(b, eb) and agree else "not settled"
    if negative(0) or s.settled is not None:
        # (settled: the last sections repeat; the window's average then still carries the
        # transient before, which can keep it from resolving below zero)
        return "periodic"
    near_zero = abs(lam[0]) + SIGNIFICANCE * err[0] <= ZERO_BAND
    if near_zero and negative(1):
        return "quasi-periodic"
    return "not settled"


def lyapunov_spectrum(
    p: Parameters,
    *,
    periods: int = DEFAULT_PERIODS,
    transient: int = DEFAULT_TRANSIENT,
    warmup: int = DEFAULT_WARMUP,
    blocks: int = DEFAULT_BLOCKS,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
    backend: str = "auto",
) -> LyapunovSpectrum:
    """The four Lyapunov exponents of the motion of Algorithm No. 2 (eqs. 18-22, with contact
    modes), from the exact tangent map along it.

    From ``state`` at ``t0`` (default the paper's step 1), the motion runs ``transient``
    periods; then an orthonormal frame of perturbations is carried by the exact free-flight and
    contact transition matrices and the saltation matrices of the impacts, captures and
    lift-offs (see the module docstring), re-orthonormalised after every event and every
    period; the first ``warmup`` periods of that product are discarded and the next
    ``periods`` averaged. The walk is the backend's (``lyapunov``,
    :mod:`impactdamper.core.backends`): the compiled kernels walk their own event loop, the
    reference its solver; the two agree to rounding where the motion is regular and within the
    errors where it is chaotic (the same events until rounding, amplified, parts them).

    Parameters
    ----------
    p : Parameters
    periods : int
        Forcing periods averaged, a multiple of ``blocks``.
    transient, warmup : int
        Periods of motion, then of tangent product, discarded (>= 0).
    blocks : int
        Blocks of the error estimate, >= 2.
    t0 : float
        Start time, s (its forcing phase is kept).
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0, e.g. a settled motion's section; default the paper's step 1.
    tolerances : Tolerances, optional
        The event solver's tolerances.
    backend : {"auto", "compiled", "python"}
        Who walks (:mod:`impactdamper.analysis.solve`).

    Returns
    -------
    LyapunovSpectrum
        With ``backend`` and ``fallback`` (why the reference walked where the kernels were
        asked).

    Raises
    ------
    TypeError, ValueError
        A bad argument, named.
    SearchLimitError
        The motion needs more work than the event solver's bound.
    """
    run, why = get_backend(backend)
    p = require_parameters(p)
    blocks = integer_argument("blocks", blocks, 2, MAX_PERIODS)
    periods = integer_argument("periods", periods, blocks, MAX_PERIODS)
    if periods % blocks:
        raise ValueError(f"`periods` = {periods!r} is not allowed: must be a multiple of `blocks` = {blocks!r}")
    transient = integer_argument("transient", transient, 0, MAX_PERIODS)
    warmup = integer_argument("warmup", warmup, 0, MAX_PERIODS)
    t0 = finite_argument("t0", t0)
    tolerances = check_tolerances(tolerances)
    state = check_start_state(state, p, tolerances)
    # The forcing's phase at t0, in [0, T): the run is the same motion shifted by whole periods.
    t_start = start_in_first_period(p, t0)
    if not p.native_scales():
        # The same relative problem in the reference case's units: exponents per period and the
        # relative quantities do not depend on the free scales.
        q = p.canonical()
        to_q, to_p = ScaleMap(p, q), ScaleMap(q, p)
        t_q = to_q.apply(t_start, "time")
        walk = run.lyapunov(q, t_q, None if state is None else to_q.full(state), tolerances, periods, transient, warmup)
        return _replace_scales(_summarise(q, walk, t_q, transient, warmup, blocks, why), p, to_p)
    walk = run.lyapunov(p, t_start, state, tolerances, periods, transient, warmup)
    return _summarise(p, walk, t_start, transient, warmup, blocks, why)


def spectrum_from_section(
    p: Parameters,
    section: np.ndarray,
    *,
    periods: int,
    tolerances: Tolerances,
    backend: str,
    warmup: int = DEFAULT_WARMUP,
    blocks: int = DEFAULT_BLOCKS,
) -> LyapunovSpectrum:
    """:func:`lyapunov_spectrum` of a point of a many-point run
    (:func:`impactdamper.analysis.batch.steady_states`) from the section its run hands on: at the
    forcing's phase 0 (the runs start at t0 = 0) and after the run's periods (a point left
    nonperiodic at its cap, or a periodic one), so no transient is run again."""
    return lyapunov_spectrum(
        p,
        state=section,
        transient=0,
        warmup=warmup,
        periods=periods,
        blocks=blocks,
        tolerances=tolerances,
        backend=backend,
    )


def _replace_scales(s: LyapunovSpectrum, p: Parameters, scales: ScaleMap) -> LyapunovSpectrum:
    return dataclasses.replace(
        s, p=p, sections=scales.full(s.sections), t_section=float(scales.apply(s.t_section, "time"))
    )


def _summarise(
    p: Parameters, walk: TangentRun, t0: float, transient: int, warmup: int, blocks: int, why: str
) -> LyapunovSpectrum:
    """The exponents (weighted averages of the walk's growths), their block errors and the
    walk's counts. ``why``: the registry's reason for the backend that walked ("")."""
    increments = walk.increments
    periods = len(increments)
    length = periods // blocks
    finite = np.isfinite(increments).all(axis=0)
    exponents = np.full(4, -math.inf)
    block_avg = np.full((blocks, 4), -math.inf)
    errors = np.full(4, math.nan)
    spreads = np.full(4, math.nan)
    exponents[finite] = birkhoff_weights(periods) @ increments[:, finite]
    block_avg[:, finite] = np.einsum(
        "bnj,n->bj", increments[:, finite].reshape(blocks, length, -1), birkhoff_weights(length)
    )
    errors[finite] = block_avg[:, finite].std(axis=0, ddof=1) / math.sqrt(blocks)
    spreads[finite] = np.ptp(block_avg[:, finite], axis=0)
    return LyapunovSpectrum(
        p=p,
        exponents=exponents,
        errors=errors,
        spreads=spreads,
        block_averages=block_avg,
        increments=increments,
        sections=walk.sections,
        t_section=float(t0),
        dimension=int(walk.dimension),
        periods=periods,
        transient=transient,
        warmup=warmup,
        blocks=blocks,
        **walk.event_counts(),
        contact_time=float(walk.contact_time / (periods * p.T)),
        backend=walk.backend,
        fallback=walk.fallback or why,
    )
