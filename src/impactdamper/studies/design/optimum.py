"""Choosing a suppressor, answered: both devices optimised by one optimiser on one criterion,
their robustness to a detuned object, their stroke and their loads.

The two devices on an object of mass ratio mu and damping delta1 (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100, eqs. 1-2 and 9-10 in relative form):

* the **impact suppressor**: a spring-damper absorber (N, delta2) whose travel x2 - x1 is stopped
  at the gap Delta0 (eq. 9), impacts by Newton's law with restitution R (eqs. 21-22); its
  max|x1|/x_st over the band is the worse of the upward and downward sweeps
  (:func:`impactdamper.studies.design.design.impact_band_response`), its peak located;
* the **linear TMD** (N, delta2), no stop, in closed form (:class:`~impactdamper.studies.design.design.LinearDevice`).

**Optimiser** (:func:`minimise`, the same for both): a scrambled Sobol sample of the parameter
box (seeded: deterministic), the criterion at every sample on a coarse grid, then Nelder-Mead
(in the box scaled to the unit cube, bounded) from the best few samples on the finer criterion.
For the TMD both stages are the exact located peak; for the impact suppressor the coarse stage
is the peak on a band grid of step ``COARSE_STEP`` and the local stage the peak on the band grid
(step :data:`~impactdamper.studies.design.design.BAND_STEP`) refined by a parabola through each local
maximum (:meth:`~impactdamper.studies.design.design.BandResponse.interpolated_peak`); with a
``polish_evaluations`` budget a last Nelder-Mead runs on the located peak itself; the optimum's
peak is then located.

**Detuning** (:func:`detuned`): the object's natural frequency omega1 is uncertain by a factor
f = 1 + e (its stiffness c1 by f^2; the masses, the suppressor and the force are what was
built). In the relative parameters theta = omega/omega1 -> theta/f (the physical band of
forcing frequencies maps to band/f), N = omega2/omega1 -> N/f, delta1 = k1/(2 m1 omega1) ->
delta1/f, delta2 = k2/(2 m2 omega1) -> delta2/f, x_st = P0/c1 -> x_st/f^2, so the gap
Delta0/x_st -> gap f^2, and an amplitude over the detuned x_st is divided by f^2 to be over the
nominal x_st (the unit every result is in). mu and R are unchanged. The worst case of a design
is the largest located peak over e on a grid of ``DETUNING_POINTS`` values in [-d, d].
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from collections.abc import Callable, Sequence

import numpy as np
import scipy.optimize
import scipy.stats

from impactdamper.analysis.point import SweepSettings
from impactdamper.core.parameters import Parameters, finite_argument
from impactdamper.core.simulate import EventDrivenSolver
from impactdamper.studies.design.design import (
    BAND_STEP,
    CRITERIA,
    BandResponse,
    LinearDevice,
    _check_band,
    den_hartog,
    impact_band_response,
)

__all__ = [
    "TIE",
    "impacting",
    "design_study",
    "robust_impact",
    "worst_within",
    "device",
    "recommendation",
    "IMPACT_BOUNDS",
    "TMD_BOUNDS",
    "COARSE_STEP",
    "DETUNING_POINTS",
    "SENSITIVITY_WORSE",
    "Optimum",
    "minimise",
    "optimise_tmd",
    "optimise_impact",
    "detuned",
    "worst_case_tmd",
    "worst_case_impact",
    "sensitivity",
    "impact_stroke_and_loads",
    "tmd_at_stroke",
    "design_optima",
    "Budget",
    "CLI_BUDGET",
    "STAGE_BUDGET",
]

# The impact suppressor's box (relative units):
# * gap Delta0/x_st in [-8, 16]: at -8 the stop is preloaded so far (spring force mu N^2 |gap| P0)
#   that over most of the band the suppressor rides on the stop, a rigidly added mass; at +16 the
#   stop lies beyond the travel of a tuned absorber (the optimal TMD's stroke is ~9.5 x_st at
#   mu = 0.08): a linear absorber. Both ends are devices of their own, so the optimum lies
#   inside (checked: ``at_bound``; with +8 the band-average optimum ran to 7.98).
# * N in [0.2, 1.5]: from a nearly free impact mass (the classic impact damper) to a spring
#   stiffer than the tuned one (1/(1 + mu)) by half.
# * delta2 in [0, 0.3]: from no damper at all (the impacts alone dissipate; the optimum of the
#   reference object runs there when the box stops at 0.005) to heavy viscous damping (zeta2 =
#   delta2/N of 0.3 at N = 1).
# * R in [0.2, 0.95]: what real stops give, a polymer pad (~0.2-0.5) to hardened steel (~0.9);
#   0 and 1 are idealisations no buffer reaches.
IMPACT_BOUNDS = {"gap": (-8.0, 16.0), "N": (0.2, 1.5), "delta2": (0.0, 0.3), "R": (0.2, 0.95)}
# The impact suppressor's gap bound of the design table's row whose stop is within reach: the
# optimal TMD's stroke is ~9.5 x_st, so a gap up to 8 meets the stop near resonance.
STOP_GAP = 8.0
# The TMD's box: the same N range, delta2 from nearly undamped to heavy (Den Hartog's optimum at
# mu = 0.08 is N = 0.93, delta2 = 0.15).
TMD_BOUNDS = {"N": (0.2, 1.5), "delta2": (0.001, 0.3)}
# The coarse stage's band grid step for the impact suppressor: twice the band grid's, enough to
# rank designs (the peaks are ~0.05 wide), at half the cost.
COARSE_STEP = 0.02
# Detuning values e in [-d, d] of a worst case (and of a robust optimum's criterion): 9 put
# +-d/2 on the grid, so that one grid over +-10 % gives the +-5 % worst case too.
DETUNING_POINTS = 9
# A parameter's sensitivity: how far it may move (the others at the optimum) before the peak is
# this much worse.
SENSITIVITY_WORSE = 0.05
# Bisection steps of a sensitivity: the move is known to 2^-12 of the box side.
SENSITIVITY_STEPS = 12
# Samples per forcing period of the stroke max|x2 - x1| (between the events, where it is
# smooth: 512 samples leave ~2e-5 relative).
STROKE_SAMPLES = 512
# Forcing periods read for a cycle that did not settle.
NONPERIODIC_PERIODS = 8


@dataclass(frozen=True)
class Budget:
    """How hard :func:`minimise` works: Sobol samples (a power of 2), local runs from the best
    of them, Nelder-Mead evaluations per local run, and (impact suppressor, peak criterion)
    Nelder-Mead evaluations of a final polish on the located peak itself (0: none)."""

    starts: int = 32
    keep: int = 2
    local_evaluations: int = 80
    polish_evaluations: int = 0


# The command's budget: a minute on two cores (one Nelder-Mead evaluation of the impact
# suppressor is a two-way sweep of ~100 points, ~0.15 s).
CLI_BUDGET = Budget(starts=32, keep=2, local_evaluations=70, polish_evaluations=10)
# The design stage's: a few minutes.
STAGE_BUDGET = Budget(starts=64, keep=3, local_evaluations=120, polish_evaluations=30)


@dataclass(frozen=True)
class Optimum:
    """A device's optimum.

    Attributes
    ----------
    device : str
        ``impact`` or ``tmd``.
    criterion : str
        ``peak`` or ``band_average`` (of max|x1|/x_st over the band, the worse sweep direction).
    parameters : dict
        The optimised parameters by name.
    peak, peak_theta : float
        The located peak of max|x1|/x_st and where.
    band_average : float
        Trapezoidal mean on the band grid.
    evaluations : int
        Criterion evaluations of the optimiser.
    at_bound : tuple of str
        Parameters within 1e-3 of the box side from a bound.
    grid_peak : float
        The peak on the band grid (the impact suppressor's local stage's criterion; equal to
        ``peak`` for the TMD).
    """

    device: str
    criterion: str
    parameters: dict
    peak: float
    peak_theta: float
    band_average: float
    evaluations: int
    at_bound: tuple = ()
    grid_peak: float = math.nan

    def to_dict(self) -> dict:
        d = {name: getattr(self, name) for name in self.__dataclass_fields__}
        d["at_bound"] = list(self.at_bound)
        return d


def _unit(bounds: dict) -> tuple[list, np.ndarray, np.ndarray]:
    names = list(bounds)
    lo = np.array([bounds[n][0] for n in names], float)
    hi = np.array([bounds[n][1] for n in names], float)
    return names, lo, hi


def minimise(
    coarse: Callable[[dict], float],
    fine: Callable[[dict], float],
    bounds: dict,
    *,
    budget: Budget = Budget(),
    seed: int = 0,
    guesses: Sequence[dict] = (),
    progress: Callable[[str], None] | None = None,
) -> tuple[dict, float, int]:
    """Global minimum of ``fine`` over the box ``bounds`` ({name: (low, high)}).

    A scrambled Sobol sample (``budget.starts`` points, ``seed``) and ``guesses`` evaluated by
    ``coarse``; Nelder-Mead (bounded, in the unit cube, initial simplex 10 % of each side,
    stopping at 1e-4 of the side and 1e-6 in the criterion) on ``fine`` from the
    ``budget.keep`` best. Returns (best parameters, fine value, evaluations).
    """
    names, lo, hi = _unit(bounds)
    d = len(names)
    to_dict = lambda u: {n: float(v) for n, v in zip(names, lo + np.clip(u, 0.0, 1.0) * (hi - lo))}  # noqa: E731
    sample = scipy.stats.qmc.Sobol(d, scramble=True, seed=seed).random(int(budget.starts))
    extra = [np.array([(g[n] - lo[i]) / (hi[i] - lo[i]) for i, n in enumerate(names)]) for g in guesses]
    points = np.vstack([sample] + [e[None, :] for e in extra]) if extra else sample
    values = []
    for j, u in enumerate(points):
        values.append(coarse(to_dict(u)))
        if progress is not None and (j + 1) % 16 == 0:
            progress(f"global stage {j + 1}/{len(points)}: best so far {np.nanmin(values):.4g}")
    order = np.argsort(np.where(np.isfinite(values), values, np.inf), kind="stable")
    evaluations = len(points)
    best_u, best_v = None, math.inf
    for rank, j in enumerate(order[: int(budget.keep)]):
        u0 = points[j]
        simplex = np.vstack(
            [u0] + [np.clip(u0 + 0.1 * np.eye(d)[i] * (1 if u0[i] < 0.5 else -1), 0, 1) for i in range(d)]
        )
        res = scipy.optimize.minimize(
            lambda u: fine(to_dict(u)),
            u0,
            method="Nelder-Mead",
            bounds=[(0.0, 1.0)] * d,
            options={"maxfev": int(budget.local_evaluations), "xatol": 1e-4, "fatol": 1e-6, "initial_simplex": simplex},
        )
        evaluations += int(res.nfev)
        if res.fun < best_v:
            best_u, best_v = np.clip(res.x, 0.0, 1.0), float(res.fun)
        if progress is not None:
            progress(
                f"local stage {rank + 1}/{min(int(budget.keep), len(order))}: {float(res.fun):.5g} "
                f"({int(res.nfev)} evaluations)"
            )
    return to_dict(best_u), best_v, evaluations


def _at_bound(x: dict, bounds: dict) -> tuple:
    return tuple(n for n, (a, b) in bounds.items() if min(x[n] - a, b - x[n]) <= 1e-3 * (b - a))


def _check(mu: float, delta1: float, band, criterion: str) -> tuple:
    mu = finite_argument("mu", mu)
    delta1 = finite_argument("delta1", delta1)
    if not mu > 0:
        raise ValueError(f"`mu` = {mu!r} is not allowed: must be > 0")
    if not delta1 >= 0:
        raise ValueError(f"`delta1` = {delta1!r} is not allowed: must be >= 0")
    if criterion not in CRITERIA:
        raise ValueError(f"`criterion` = {criterion!r} is not allowed: must be one of {', '.join(CRITERIA)}")
    return mu, delta1, _check_band(band)


def _tmd_criterion(mu, delta1, band, criterion, detuning: float = 0.0) -> Callable[[dict], float]:
    def f(x: dict) -> float:
        if detuning > 0:
            return worst_case_tmd(mu, delta1, x["N"], x["delta2"], band, detuning)
        d = LinearDevice(mu, x["N"], delta1, x["delta2"])
        return d.peak(band)[1] if criterion == "peak" else d.band_average(band)

    return f


def _tmd_optimum(mu, delta1, band, criterion, x, evaluations, bounds) -> Optimum:
    d = LinearDevice(mu, x["N"], delta1, x["delta2"])
    t, v = d.peak(band)
    return Optimum(
        "tmd", criterion, dict(x), float(v), float(t), d.band_average(band), evaluations, _at_bound(x, bounds), float(v)
    )


def optimise_tmd(
    mu: float,
    delta1: float,
    band: tuple[float, float] = (0.5, 1.5),
    criterion: str = "peak",
    *,
    bounds: dict | None = None,
    budget: Budget = STAGE_BUDGET,
    detuning: float = 0.0,
    seed: int = 0,
) -> Optimum:
    """The linear TMD (N, delta2) minimising ``criterion`` over ``band``, by :func:`minimise`
    (the impact suppressor's optimiser) on the exact located peak (closed form). With
    ``detuning`` d > 0 the criterion is the worst-case peak over the object's frequency
    uncertain by +-d (the robust optimum; :func:`worst_case_tmd`)."""
    mu, delta1, band = _check(mu, delta1, band, criterion)
    bounds = dict(TMD_BOUNDS if bounds is None else bounds)
    f = _tmd_criterion(mu, delta1, band, criterion, detuning)
    dh = den_hartog(mu)
    guess = [
        {
            "N": min(max(dh["N"], bounds["N"][0]), bounds["N"][1]),
            "delta2": min(max(dh["delta2"], bounds["delta2"][0]), bounds["delta2"][1]),
        }
    ]
    x, _, n = minimise(f, f, bounds, budget=budget, seed=seed, guesses=guess)
    return _tmd_optimum(mu, delta1, band, criterion, x, n, bounds)


def _impact_parameters(mu: float, delta1: float, x: dict) -> Parameters:
    return Parameters(mu=mu, delta1=delta1, N=x["N"], delta2=x["delta2"], R=x["R"], gap=x["gap"])


def _impact_value(mu, delta1, band, criterion, step, settings, locate=False) -> Callable[[dict], float]:
    def f(x: dict) -> float:
        try:
            r = impact_band_response(_impact_parameters(mu, delta1, x), band, step, locate=locate, settings=settings)
        except (ValueError, RuntimeError, ArithmeticError):
            return math.inf  # a design the solver cannot settle is not a design to recommend
        if criterion == "peak":
            return r.peak if locate else r.interpolated_peak()
        return r.band_average

    return f


def optimise_impact(
    mu: float,
    delta1: float,
    band: tuple[float, float] = (0.5, 1.5),
    criterion: str = "peak",
    *,
    bounds: dict | None = None,
    budget: Budget = STAGE_BUDGET,
    settings: SweepSettings | None = None,
    seed: int = 0,
    guesses: Sequence[dict] = (),
    step: float = BAND_STEP,
    coarse_step: float = COARSE_STEP,
    progress: Callable[[str], None] | None = None,
) -> tuple[Optimum, BandResponse]:
    """The impact suppressor (gap, N, delta2, R) minimising ``criterion`` over ``band`` at the
    given ``mu`` and ``delta1``, by :func:`minimise`: the coarse stage on the band grid of step
    ``coarse_step``, the local stage on the band grid of step ``step`` (peaks sampled there),
    then the optimum's peak located (:func:`~impactdamper.studies.design.design.impact_band_response`).

    Returns
    -------
    (Optimum, BandResponse)
        The optimum and its located band response.
    """
    mu, delta1, band = _check(mu, delta1, band, criterion)
    bounds = dict(IMPACT_BOUNDS if bounds is None else bounds)
    settings = settings or SweepSettings()
    coarse = _impact_value(mu, delta1, band, criterion, coarse_step, settings)
    fine = _impact_value(mu, delta1, band, criterion, step, settings)
    x, _, n = minimise(coarse, fine, bounds, budget=budget, seed=seed, guesses=guesses, progress=progress)
    if criterion == "peak" and budget.polish_evaluations > 0:
        # The polish: Nelder-Mead on the located peak from the local stage's optimum, a simplex of
        # 2 % of each side (the local stage's peak is the grid's, interpolated).
        located = _impact_value(mu, delta1, band, criterion, step, settings, locate=True)
        names, lo, hi = _unit(bounds)
        u0 = np.array([(x[k] - lo[i]) / (hi[i] - lo[i]) for i, k in enumerate(names)])
        simplex = np.vstack(
            [u0]
            + [np.clip(u0 + 0.02 * np.eye(len(names))[i] * (1 if u0[i] < 0.5 else -1), 0, 1) for i in range(len(names))]
        )
        to_dict = lambda u: {k: float(v) for k, v in zip(names, lo + np.clip(u, 0.0, 1.0) * (hi - lo))}  # noqa: E731
        res = scipy.optimize.minimize(
            lambda u: located(to_dict(u)),
            u0,
            method="Nelder-Mead",
            bounds=[(0.0, 1.0)] * len(names),
            options={
                "maxfev": int(budget.polish_evaluations),
                "xatol": 1e-4,
                "fatol": 1e-6,
                "initial_simplex": simplex,
            },
        )
        n += int(res.nfev)
        x = to_dict(res.x)
        if progress is not None:
            progress(f"polish on the located peak: {float(res.fun):.5g} ({int(res.nfev)} evaluations)")
    r = impact_band_response(_impact_parameters(mu, delta1, x), band, step, settings=settings)
    return Optimum(
        "impact", criterion, dict(x), r.peak, r.peak_theta, r.band_average, n, _at_bound(x, bounds), r.grid_peak()
    ), r


def detuned(p: Parameters, band: tuple[float, float], e: float) -> tuple[Parameters, tuple, float]:
    """The system whose object's natural frequency is (1 + e) omega1 (module docstring).

    Returns
    -------
    (Parameters, band, scale)
        The detuned relative parameters, the physical band in the detuned theta, and the factor
        1/(1 + e)^2 that puts an amplitude over the detuned x_st into the nominal x_st.
    """
    f = 1.0 + finite_argument("detuning", e)
    if not f > 0:
        raise ValueError(f"`detuning` = {e!r} is not allowed: must be > -1")
    q = p.replace(N=p.N / f, delta1=p.delta1 / f, delta2=p.delta2 / f, gap=p.gap * f * f)
    return q, (band[0] / f, band[1] / f), 1.0 / (f * f)


def _detunings(d: float) -> np.ndarray:
    return np.linspace(-d, d, DETUNING_POINTS)


def worst_case_tmd(mu: float, delta1: float, N: float, delta2: float, band, d: float) -> float:
    """The TMD's largest located peak over the object's frequency detuned by e in [-d, d]
    (``DETUNING_POINTS`` values), over the nominal x_st."""
    out = 0.0
    for e in _detunings(d):
        f = 1.0 + e
        dev = LinearDevice(mu, N / f, delta1 / f, delta2 / f)
        out = max(out, float(dev.peak((band[0] / f, band[1] / f))[1]) / (f * f))
    return float(out)


def worst_case_impact(
    p: Parameters,
    band,
    d: float,
    *,
    settings: SweepSettings | None = None,
    locate: bool = True,
    step: float = BAND_STEP,
) -> dict:
    """The impact suppressor's located peak at each detuning e in [-d, d] (``DETUNING_POINTS``
    values), over the nominal x_st. Returns {"detunings": [...], "peaks": [...], "worst": max}."""
    peaks = []
    es = _detunings(d)
    for e in es:
        q, b, scale = detuned(p, band, float(e))
        r = impact_band_response(q, b, step, locate=locate, settings=settings)
        peaks.append(scale * (r.peak if locate else r.grid_peak()))
    return {"detunings": [float(e) for e in es], "peaks": peaks, "worst": float(max(peaks))}


def worst_within(case: dict, d: float) -> float:
    """The worst peak of a :func:`worst_case_impact` result over |e| <= d."""
    return float(max(v for e, v in zip(case["detunings"], case["peaks"]) if abs(e) <= d + 1e-12))


def sensitivity(value: Callable[[dict], float], x: dict, bounds: dict, worse: float = SENSITIVITY_WORSE) -> dict:
    """How far each parameter of the optimum ``x`` may move, the others fixed, before
    ``value`` is ``worse`` (fraction) above its value at ``x``: per name and side, the move
    located by bisection (SENSITIVITY_STEPS steps) between x and the bound, or None when even
    the bound is not that much worse. Returns {name: {"down": move or None, "up": move or None}}."""
    limit = (1.0 + worse) * value(x)
    out = {}
    for n, (a, b) in bounds.items():
        out[n] = {}
        for side, end in (("down", a), ("up", b)):
            if abs(end - x[n]) <= 0:
                out[n][side] = 0.0
                continue
            if value({**x, n: end}) <= limit:
                out[n][side] = None
                continue
            lo, hi = x[n], end
            for _ in range(SENSITIVITY_STEPS):
                mid = 0.5 * (lo + hi)
                if value({**x, n: mid}) <= limit:
                    lo = mid
                else:
                    hi = mid
            out[n][side] = float(abs(0.5 * (lo + hi) - x[n]))
    return out


def _cycle(p: Parameters, theta: float, section: np.ndarray, k: int) -> dict:
    """One settled cycle from its section: stroke max|x2 - x1|/x_st and the pulses."""
    q = p.replace(theta=float(theta))
    periods = k if k > 0 else NONPERIODIC_PERIODS
    solver = EventDrivenSolver(q, t0=0.0, state=np.array(section, float))
    end = periods * q.T
    solver.advance(end)
    traj = solver.trajectory
    ts = np.linspace(0.0, end, STROKE_SAMPLES * periods + 1)
    full, _ = traj.sample(ts)
    stroke = float(np.max(np.abs(full[:, 1] - full[:, 0]))) / q.x_st
    events = [e for e in traj.events if e.t < end and e.kind in ("impact", "stick")]
    pulses = np.array([abs(e.impulse) for e in events])
    impacts = sum(1 for e in events if e.kind == "impact")
    omega1 = q.omega / q.theta
    P0 = q.m1 * omega1 * omega1 * q.x_st
    return {
        "stroke": stroke,
        "impacts_per_period": impacts / periods,
        "impulse": float(pulses.max()) * omega1 / P0 if len(pulses) else 0.0,
        "mean_force": float(pulses.sum()) / end / P0,
    }


def impact_stroke_and_loads(r: BandResponse) -> dict:
    """Stroke and loads of an impact suppressor over its band grid, both directions (each
    grid point's settled cycle run afresh from its section, stroke sampled STROKE_SAMPLES per
    period).

    Returns
    -------
    dict
        ``stroke``: max|x2 - x1|/x_st; ``impulse_per_impact``: the largest pulse S over P0/omega1;
        ``impacts_per_second``: the most impacts per second over f1 = omega1/(2 pi) (impacts
        per period times theta); ``mean_force``: the largest mean force the impacts (and
        captures) transmit, sum of S over the cycle's duration, over P0; each with its theta.
        The stereomechanical impact (eqs. 21-22) is instantaneous: it gives pulses, no contact
        force peak (that needs the stop's stiffness, which the model does not have).
    """
    best = {
        "stroke": (0.0, math.nan),
        "impulse_per_impact": (0.0, math.nan),
        "impacts_per_second": (0.0, math.nan),
        "mean_force": (0.0, math.nan),
    }
    for sections, ks in ((r.up_sections, r.up_k), (r.down_sections, r.down_k)):
        for t, s, k in zip(r.thetas, sections, ks):
            c = _cycle(r.p, float(t), s, int(k))
            for key, v in (
                ("stroke", c["stroke"]),
                ("impulse_per_impact", c["impulse"]),
                ("impacts_per_second", c["impacts_per_period"] * float(t)),
                ("mean_force", c["mean_force"]),
            ):
                if v > best[key][0]:
                    best[key] = (float(v), float(t))
    out = {k: v for k, (v, _) in best.items()}
    out.update({f"{k}_theta": t for k, (_, t) in best.items()})
    return out


def tmd_at_stroke(
    mu: float,
    delta1: float,
    band,
    max_stroke: float,
    criterion: str = "peak",
    *,
    budget: Budget = STAGE_BUDGET,
    seed: int = 0,
) -> Optimum:
    """The best TMD whose stroke max|x2 - x1|/x_st over the band does not exceed ``max_stroke``
    (closed form), by :func:`minimise` with the excess stroke as a penalty (a design over the
    limit scores 1e3 per unit of relative excess above any within it)."""
    mu, delta1, band = _check(mu, delta1, band, criterion)
    max_stroke = finite_argument("max_stroke", max_stroke)
    if not max_stroke > 0:
        raise ValueError(f"`max_stroke` = {max_stroke!r} is not allowed: must be > 0")
    plain = _tmd_criterion(mu, delta1, band, criterion)

    def f(x: dict) -> float:
        s = LinearDevice(mu, x["N"], delta1, x["delta2"]).stroke_peak(band)[1]
        return plain(x) + 1e3 * max(0.0, s / max_stroke - 1.0)

    x, _, n = minimise(f, f, TMD_BOUNDS, budget=budget, seed=seed)
    return _tmd_optimum(mu, delta1, band, criterion, x, n, TMD_BOUNDS)


def _device_summary(opt: Optimum, worst: dict, stroke_loads: dict) -> dict:
    return {**opt.to_dict(), "worst_case": worst, **stroke_loads}


def design_optima(
    band: tuple[float, float],
    mu: float,
    delta1: float,
    *,
    detuning: float = 0.1,
    max_stroke: float | None = None,
    criterion: str = "peak",
    budget: Budget = CLI_BUDGET,
    settings: SweepSettings | None = None,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Both devices optimised for one object and band: what ``python -m impactdamper design``
    prints.

    Parameters
    ----------
    band : (float, float)
        theta = omega/omega1 band (the object's nominal omega1).
    mu, delta1 : float
        Mass ratio (> 0) and the object's damping (>= 0).
    detuning : float
        The object's natural frequency uncertain by +-detuning (in [0, 0.5]).
    max_stroke : float, optional
        The equal-stroke TMD's limit of max|x2 - x1|/x_st (default: the impact suppressor's).
    criterion : str
        ``peak`` or ``band_average``.
    budget : Budget
    settings : SweepSettings, optional
    seed : int
    progress : callable(str), optional

    Returns
    -------
    dict
        ``band``, ``mu``, ``delta1``, ``detuning``, ``criterion``; ``impact`` (its gap at most
        STOP_GAP, the stop within reach: with a gap past its travel the optimum is the TMD),
        ``tmd`` and
        ``tmd_equal_stroke``, each: ``parameters``, ``peak``, ``peak_theta``, ``band_average``,
        ``worst_case`` (its peak at the worst detuning within +-detuning), ``stroke``, and for the
        impact suppressor the loads ``impulse_per_impact`` (P0/omega1), ``impacts_per_second``
        (f1), ``mean_force`` (P0) and ``clearance`` (Delta0 over P0/c1, = the gap); ``ratio``:
        impact over TMD of peak, band average and worst case; ``elapsed`` (s).
    """
    t0 = time.perf_counter()
    mu, delta1, band = _check(mu, delta1, band, criterion)
    detuning = finite_argument("detuning", detuning)
    if not 0.0 <= detuning <= 0.5:
        raise ValueError(f"`detuning` = {detuning!r} is not allowed: must be in [0, 0.5]")
    if max_stroke is not None:
        max_stroke = finite_argument("max_stroke", max_stroke)
        if not max_stroke > 0:
            raise ValueError(f"`max_stroke` = {max_stroke!r} is not allowed: must be > 0")
    say = progress or (lambda s: None)
    say("optimising the TMD")
    tmd = optimise_tmd(mu, delta1, band, criterion, budget=budget, seed=seed)
    say(
        f"TMD: N = {tmd.parameters['N']:.4f}, delta2 = {tmd.parameters['delta2']:.4f}, peak {tmd.peak:.4f}; "
        "optimising the impact suppressor"
    )
    # The stop within reach (gap <= STOP_GAP): with a gap past its travel the optimum is a TMD.
    imp, resp = optimise_impact(
        mu,
        delta1,
        band,
        criterion,
        bounds=dict(IMPACT_BOUNDS, gap=(IMPACT_BOUNDS["gap"][0], STOP_GAP)),
        budget=budget,
        settings=settings,
        seed=seed,
        progress=say,
    )
    say(f"impact: {imp.parameters}, located peak {imp.peak:.4f}; worst cases over +-{detuning:g}")
    imp_worst = (
        worst_case_impact(resp.p, band, detuning, settings=settings)
        if detuning > 0
        else {"detunings": [0.0], "peaks": [imp.peak], "worst": imp.peak}
    )
    tmd_worst = worst_case_tmd(mu, delta1, tmd.parameters["N"], tmd.parameters["delta2"], band, detuning)
    say("stroke and loads")
    loads = impact_stroke_and_loads(resp)
    tmd_stroke = LinearDevice(mu, tmd.parameters["N"], delta1, tmd.parameters["delta2"]).stroke_peak(band)[1]
    limit = loads["stroke"] if max_stroke is None else max_stroke
    eq = tmd_at_stroke(mu, delta1, band, limit, criterion, budget=budget, seed=seed)
    eq_stroke = LinearDevice(mu, eq.parameters["N"], delta1, eq.parameters["delta2"]).stroke_peak(band)[1]
    eq_worst = worst_case_tmd(mu, delta1, eq.parameters["N"], eq.parameters["delta2"], band, detuning)
    out = {
        "band": list(band),
        "mu": mu,
        "delta1": delta1,
        "detuning": detuning,
        "criterion": criterion,
        "impact": {
            **imp.to_dict(),
            "worst_case": imp_worst["worst"],
            "worst_case_detunings": imp_worst["detunings"],
            "worst_case_peaks": imp_worst["peaks"],
            **loads,
            "clearance": imp.parameters["gap"],
        },
        "tmd": {**tmd.to_dict(), "worst_case": tmd_worst, "stroke": tmd_stroke},
        "tmd_equal_stroke": {**eq.to_dict(), "worst_case": eq_worst, "stroke": eq_stroke, "max_stroke": limit},
    }
    out["ratio"] = {
        "peak": imp.peak / tmd.peak,
        "band_average": imp.band_average / tmd.band_average,
        "worst_case": imp_worst["worst"] / tmd_worst,
    }
    out["elapsed"] = time.perf_counter() - t0
    return out


def robust_impact(
    mu: float,
    delta1: float,
    band,
    d: float,
    start: dict,
    *,
    evaluations: int = 40,
    settings: SweepSettings | None = None,
    step: float = COARSE_STEP,
    bounds: dict | None = None,
) -> dict:
    """The impact suppressor's robust optimum near ``start``: Nelder-Mead (the optimiser's local
    stage, ``evaluations`` at most) on the worst grid peak (step ``step``) over the detunings
    -d, -d/2, 0, d/2, d, within ``bounds`` (default IMPACT_BOUNDS). Returns the parameters (a
    local answer: no global stage, for cost)."""
    bounds = IMPACT_BOUNDS if bounds is None else bounds

    def f(x: dict) -> float:
        worst = 0.0
        for e in np.linspace(-d, d, 5):
            try:
                q, b, scale = detuned(_impact_parameters(mu, delta1, x), band, float(e))
                r = impact_band_response(q, b, step, locate=False, settings=settings)
                worst = max(worst, scale * r.grid_peak())
            except (ValueError, RuntimeError, ArithmeticError):
                return math.inf
        return worst

    x, _, _ = minimise(f, f, bounds, budget=Budget(starts=1, keep=1, local_evaluations=evaluations), guesses=[start])
    return x


def design_study(
    band,
    mu: float,
    delta1: float,
    paper: Parameters,
    detunings: Sequence[float] = (0.05, 0.1),
    *,
    budget: Budget = STAGE_BUDGET,
    step: float = BAND_STEP,
    coarse_step: float = COARSE_STEP,
    robust_evaluations: int = 40,
    settings: SweepSettings | None = None,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """The design stage's record: every device of the design table, each with its parameters,
    located peak, band average, worst case at each detuning, stroke and (impact) loads.

    Devices: the bare object; the absorber without a stop and the impact suppressor with the
    paper's N, delta2, R at ``paper.gap`` (``paper``); the optimal TMD and the impact suppressor
    optimised jointly (gap, N, delta2, R), each for the peak and for the band average; the best
    TMD with the impact optimum's stroke; each device's robust optimum for the largest
    detuning (the TMD's global, the impact suppressor's local from its nominal optimum:
    :func:`robust_impact`, from the impact suppressor that meets its stop, gap <= STOP_GAP); and
    the sensitivity of the TMD's and that impact suppressor's peak optima (SENSITIVITY_WORSE).
    """
    say = progress or (lambda m: None)
    mu, delta1, band = _check(mu, delta1, band, "peak")
    settings = settings or SweepSettings()
    dmax = max(detunings)
    rows = []

    def linear_row(name: str, N: float, delta2: float, bare: bool = False, extra: dict | None = None) -> dict:
        dev = LinearDevice(0.0 if bare else mu, N, delta1, delta2)
        t, v = dev.peak(band)
        worst = {}
        for d in detunings:
            w = 0.0
            for e in _detunings(d):
                f = 1.0 + e
                de = LinearDevice(0.0 if bare else mu, N / f, delta1 / f, delta2 / f)
                w = max(w, de.peak((band[0] / f, band[1] / f))[1] / (f * f))
            worst[f"{d:g}"] = w
        return {
            "device": name,
            "kind": "linear",
            "parameters": {} if bare else {"N": N, "delta2": delta2},
            "peak": v,
            "peak_theta": t,
            "band_average": dev.band_average(band, step),
            "worst_case": worst,
            "stroke": 0.0 if bare else dev.stroke_peak(band)[1],
            **(extra or {}),
        }

    def impact_row(name: str, x: dict, extra: dict | None = None) -> dict:
        p = _impact_parameters(mu, delta1, x)
        r = impact_band_response(p, band, step, settings=settings)
        case = worst_case_impact(p, band, dmax, settings=settings, step=step)
        loads = impact_stroke_and_loads(r)
        say(
            f"{name}: peak {r.peak:.4f} at theta {r.peak_theta:.4f}, band average {r.band_average:.4f}, "
            f"worst case {case['worst']:.4f}, stroke {loads['stroke']:.3f}"
        )
        return {
            "device": name,
            "kind": "impact",
            "parameters": dict(x),
            "peak": r.peak,
            "peak_theta": r.peak_theta,
            "grid_peak": r.grid_peak(),
            "band_average": r.band_average,
            "worst_case": {f"{d:g}": worst_within(case, d) for d in detunings},
            "detuned_peaks": {"detunings": case["detunings"], "peaks": case["peaks"]},
            "located_peaks": [q.to_dict() for q in r.peaks],
            **loads,
            "clearance": x["gap"],
            **(extra or {}),
        }

    say("linear references")
    rows.append(linear_row("bare object", 1.0, 0.0, bare=True))
    rows.append(linear_row("absorber without a stop", paper.N, paper.delta2))
    paper_x = {"gap": paper.gap, "N": paper.N, "delta2": paper.delta2, "R": paper.R}
    rows.append(impact_row("impact, paper's N, delta2, R", paper_x))
    optima = {}
    # The impact suppressor whose stop must be within reach: its gap at most STOP_GAP (the full
    # box lets the gap run past the travel, where the device is a TMD that never impacts; and the
    # two boxes' searches check each other, the optimiser being global in intent, not proven).
    near = dict(IMPACT_BOUNDS, gap=(IMPACT_BOUNDS["gap"][0], STOP_GAP))
    for criterion in CRITERIA:
        text = criterion.replace("_", " ")
        t = optimise_tmd(mu, delta1, band, criterion, budget=budget, seed=seed)
        say(f"TMD ({criterion}): {t.parameters}")
        rows.append(
            linear_row(
                f"TMD, optimal {text}",
                t.parameters["N"],
                t.parameters["delta2"],
                extra={"evaluations": t.evaluations, "at_bound": list(t.at_bound)},
            )
        )
        for box, suffix in ((IMPACT_BOUNDS, ""), (near, f", gap <= {STOP_GAP:g}")):
            o, _ = optimise_impact(
                mu,
                delta1,
                band,
                criterion,
                bounds=box,
                budget=budget,
                settings=settings,
                seed=seed,
                guesses=[paper_x],
                step=step,
                coarse_step=coarse_step,
                progress=say,
            )
            say(f"impact ({criterion}{suffix}): {o.parameters}")
            rows.append(
                impact_row(
                    f"impact, optimal {text}{suffix}",
                    o.parameters,
                    {"evaluations": o.evaluations, "at_bound": list(o.at_bound)},
                )
            )
            if not suffix:
                optima[criterion] = (t, o)
    tmd, imp = optima["peak"]
    imp_row = impacting(rows)
    eq = tmd_at_stroke(mu, delta1, band, imp_row["stroke"], budget=budget, seed=seed)
    rows.append(
        linear_row(
            "TMD, impact's stroke", eq.parameters["N"], eq.parameters["delta2"], extra={"max_stroke": imp_row["stroke"]}
        )
    )
    say(f"robust optima (+-{dmax:g})")
    rt = optimise_tmd(mu, delta1, band, "peak", budget=budget, seed=seed, detuning=dmax)
    rows.append(linear_row(f"TMD, robust +-{100 * dmax:g} %", rt.parameters["N"], rt.parameters["delta2"]))
    # From the impact suppressor that meets its stop, with the stop kept within reach (from the
    # full box's optimum, a TMD when its gap is past its travel, the search stays a TMD).
    rx = robust_impact(
        mu,
        delta1,
        band,
        dmax,
        imp_row["parameters"],
        evaluations=robust_evaluations,
        settings=settings,
        step=coarse_step,
        bounds=near,
    )
    rows.append(impact_row(f"impact, robust +-{100 * dmax:g} %", rx))
    say("sensitivity")
    tmd_value = _tmd_criterion(mu, delta1, band, "peak")
    imp_value = _impact_value(mu, delta1, band, "peak", step, settings)
    sens = {
        "tmd": sensitivity(tmd_value, tmd.parameters, TMD_BOUNDS),
        "impact": sensitivity(imp_value, imp_row["parameters"], near),
    }
    return {
        "band": list(band),
        "mu": mu,
        "delta1": delta1,
        "detunings": list(detunings),
        "step": step,
        "coarse_step": coarse_step,
        "budget": {
            "starts": budget.starts,
            "keep": budget.keep,
            "local_evaluations": budget.local_evaluations,
            "polish_evaluations": budget.polish_evaluations,
            "robust_evaluations": robust_evaluations,
        },
        "bounds": {"impact": IMPACT_BOUNDS, "tmd": TMD_BOUNDS},
        "devices": rows,
        "sensitivity": sens,
        "sensitivity_worse": SENSITIVITY_WORSE,
    }


def device(record: dict, name: str) -> dict:
    """The row ``name`` of a :func:`design_study` record's devices (ValueError naming it if absent)."""
    for d in record["devices"]:
        if d["device"] == name:
            return d
    raise ValueError(
        f"`device` = {name!r} is not allowed: must be one of {', '.join(repr(d['device']) for d in record['devices'])}"
    )


# Two devices whose criteria differ by less than this (relative) are equal for a designer: the
# worst case is sampled at DETUNING_POINTS detunings, and the optimiser's optimum is not proven
# global; a 2 % difference is within what a second run with another seed may change.
TIE = 0.02


def _compare(impact: float, tmd: float, what: str, xst: str, pct: str) -> tuple[str, str]:
    """(winner or "tie", clause) for one criterion."""
    if abs(impact - tmd) <= TIE * min(impact, tmd):
        return "tie", f"{what} they are equal within {100 * TIE:g}{pct} (impact {impact:.2f}, TMD {tmd:.2f}{xst})"
    if tmd < impact:
        return "TMD", f"{what} the TMD is lower ({tmd:.2f} against {impact:.2f}{xst})"
    return "impact", f"{what} the impact suppressor is lower ({impact:.2f} against {tmd:.2f}{xst})"


def impacting(devices: Sequence[dict], criterion: str = "peak") -> dict:
    """The impact suppressor of a design table that a recommendation weighs for ``criterion``:
    the lower criterion of the optima whose stop is reached somewhere in the band (impacts > 0);
    the full box's optimum may put its gap beyond its travel and so be a TMD that never impacts."""
    rows = [d for d in devices if d["device"].startswith(f"impact, optimal {criterion.replace('_', ' ')}")]
    hitting = [d for d in rows if d.get("impacts_per_second", 0) > 0]
    return min(hitting or rows, key=lambda d: d[criterion])


def recommendation(
    record: dict,
    pm: str = "+-",
    pct: str = " %",
    xst: str = " x_st",
    clearance: str = "Delta0 = {gap:.2f} P0/c1",
    force: str = "P0",
) -> str:
    """One plain recommendation from a :func:`design_study` record: which device to build, on
    the nominal optima's located peaks, the robust optima's worst cases at the largest detuning,
    the band-average optima and the strokes; differences within TIE count as equal (``pm``,
    ``pct``, ``xst``, ``clearance``, ``force``: how to write plus-minus, per cent, the unit x_st,
    the clearance with its ``{gap}`` and the force amplitude)."""
    imp, tmd = impacting(record["devices"]), device(record, "TMD, optimal peak")
    impa, tmda = impacting(record["devices"], "band_average"), device(record, "TMD, optimal band average")
    dmax = max(record["detunings"])
    key = f"{dmax:g}"
    rob_i = next(d for d in record["devices"] if d["device"].startswith("impact, robust"))
    rob_t = next(d for d in record["devices"] if d["device"].startswith("TMD, robust"))
    d = f"{100 * dmax:g}"
    peak = _compare(imp["peak"], tmd["peak"], "tuned to a known frequency, at the peak", xst, pct)
    worst = _compare(
        rob_i["worst_case"][key],
        rob_t["worst_case"][key],
        f"designed for a frequency off by up to {pm}{d}{pct}, in the worst case",
        xst,
        pct,
    )
    avg = _compare(impa["band_average"], tmda["band_average"], "optimised for the band average", xst, pct)
    choice = worst[0] if worst[0] != "tie" else peak[0]
    first = {"TMD": "Build the linear TMD", "impact": "Build the impact suppressor", "tie": "Either device does"}[
        choice
    ]
    stroke = f"The TMD's stroke is {tmd['stroke']:.1f}{xst} against the impact suppressor's {imp['stroke']:.1f}: " + (
        "the stop does not shorten the travel here"
        if tmd["stroke"] <= imp["stroke"]
        else "the stop shortens the travel"
    )
    if "impact" not in (peak[0], worst[0], avg[0]):
        avg = (avg[0], avg[1] + f"; no criterion favours the impact suppressor by more than {100 * TIE:g}{pct}")
    return (
        f"{first}: {peak[1]}; {worst[1]}; {avg[1]}. {stroke}, and the impact suppressor's gap, a clearance "
        f"{clearance.format(gap=imp['parameters']['gap'])}, is optimal only at the design force amplitude {force}."
    )
