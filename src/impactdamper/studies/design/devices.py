"""The two devices a designer weighs, their criteria under every uncertainty, and their loads.

* the **impact suppressor** (gap, N, delta2, R): a spring-damper absorber whose travel x2 - x1
  is stopped at Delta0 (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100, eq. 9),
  impacts by Newton's law with restitution R (eqs. 21-22); judged on its worst branch over the
  band (:func:`impactdamper.analysis.peaks.worst_branches`);
* the **linear TMD** (N, delta2), no stop, in closed form
  (:class:`impactdamper.analysis.linear_device.LinearDevice`).

**Uncertainties** (:class:`Uncertainty`), each a set of scenarios (e, a, r):

* *detuning*: the object's natural frequency is (1 + e) omega1, e in {-d, 0, d} (its stiffness
  c1 by (1 + e)^2; the masses, the suppressor and the force are what was built). In relative
  terms theta -> theta/f (the physical band maps to band/f), N, delta1, delta2 -> /f, x_st ->
  x_st/f^2 so gap -> gap f^2, and an amplitude over the detuned x_st is divided by f^2 to be over
  the nominal x_st (f = 1 + e);
* *force amplitude*: P0 -> a P0, a in {a_low, 1, a_high}: x_st scales with a, so the clearance
  Delta0 is gap/a of the new x_st, and max|x1|/x_st is read per unit of the actual force (a
  linear device's is unchanged);
* *restitution drift*: R -> R + r, r in {-r0, 0, r0}, clipped to [R_LOW, R_HIGH] (wear, heat);
* *absorber*: the absorber's own spring c2 off by +-stiffness (N -> N sqrt(1 + k)) and its
  damper off by +-damping (delta2 -> delta2 (1 + c)), k and c alone and at the 4 corners: the
  mistuning that both devices, the TMD and the impact suppressor, meet alike (a spring's
  tolerance, a viscous damper's drift with temperature);
* *together*: all at once: the nominal scenario, each one's two ends alone, and the 32 corners
  of the box of the five (43 scenarios; for a linear TMD the force and the restitution change
  nothing).

A criterion is the nominal peak, the nominal band average, or the worst peak over one
uncertainty's scenarios (or over all together). Loads: the stroke max|x2 - x1|/x_st, the largest
pulse, the impacts per period and per hour at a stated natural frequency, and the peak contact
force of a linear spring stop of stiffness kappa c1 (:func:`impact_loads`).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from collections.abc import Sequence

import numpy as np

from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.analysis.parallel import map_blocks
from impactdamper.analysis.peaks import SEARCH_THETA_TOL, STEP, THETA_TOL, RANDOM_COUNT, band_points, worst_branches
from impactdamper.analysis.point import SweepSettings
from impactdamper.core.parameters import Parameters

__all__ = [
    "CRITERIA",
    "ROBUST",
    "Uncertainty",
    "Scenario",
    "impact_parameters",
    "ImpactCriterion",
    "TmdCriterion",
    "impact_rows",
    "tmd_row",
    "IMPACT_NAMES",
    "TMD_NAMES",
    "R_LOW",
    "R_HIGH",
    "STOP_STIFFNESS",
    "NATURAL_FREQUENCY",
    "WORKERS",
    "STROKE_PENALTY",
    "DESIGN_SETTINGS",
    "RANGES",
]

CRITERIA = ("peak", "band_average", "detuning", "force", "restitution", "absorber", "together")
# The robust criteria: the worst peak over one uncertainty (or all together).
ROBUST = ("detuning", "force", "restitution", "absorber", "together")
# The design variables, defined here only: the TMD's tuning and damping, and the impact
# suppressor's, its gap first and its restitution last (the search box's order).
TMD_NAMES = ("N", "delta2")
IMPACT_NAMES = ("gap", *TMD_NAMES) + ("R",)
# Restitution a drifting stop may reach: a soft pad to hard steel (0 and 1 are idealisations).
R_LOW, R_HIGH = 0.05, 0.98
# The stop's stiffness over the object's spring c1, for the contact force: a steel stop on a
# structure is 10^2 to 10^4 times stiffer than the suspension it protects.
STOP_STIFFNESS = 1000.0
# The object's natural frequency f1 = omega1/(2 pi) at which impacts are counted per hour, Hz.
NATURAL_FREQUENCY = 10.0
# Processes of the design command's batch calls and searches (the answer does not depend on
# them): the two cores its time is quoted for. Here, not in optimum.py, so that the command
# line's parser reads it without importing the search (scipy.stats: 0.5 s on every command).
WORKERS = 2
# A design over its stroke limit scores its criterion times (1 + STROKE_PENALTY x the relative
# excess): 1 % over the limit doubles it, and the search still sees which way the limit lies.
STROKE_PENALTY = 100.0
# Forcing periods read for a cycle that did not settle (its loads).
NONPERIODIC_PERIODS = 8
# Samples per forcing period of the stroke (between events, where the motion is smooth: ~1e-4).
STROKE_SAMPLES = 256
# The documented ranges of the command (and of design_optima): the work a design takes is
# bounded by them (a band of at most 2 in theta is at most 101 grid points; a mass ratio or a
# damping below them makes resonances too sharp for the band grid, and the object's own peak
# unbounded at delta1 = 0).
RANGES = {
    "mu": (0.01, 0.25),
    "delta1": (0.005, 0.2),
    "theta_start": (0.2, 2.0),
    "theta_stop": (0.4, 3.0),
    "band_width": (0.2, 2.0),
    "detuning": (0.0, 0.3),
    "force_low": (0.1, 1.0),
    "force_high": (1.0, 10.0),
    "restitution_drift": (0.0, 0.5),
    "stiffness_drift": (0.0, 0.3),
    "damping_drift": (0.0, 0.9),
    "stop_stiffness": (1.0, 1e6),
    "natural_frequency": (1e-3, 1e4),
}
# How every motion of the design is settled: the sweeps' settings (settle tolerance 1e-9, 150
# periods, 50 after a nonperiodic neighbour, cycles up to 8 T), the same for the command and the
# workflow, without the Newton rescue of a motion that does not settle within the cap: such a
# motion counts with its largest |x1| over its run (at the reference object's optimum a quarter
# of the grid's points were handed to the rescue, which tripled the cost and changed no peak).
DESIGN_SETTINGS = SweepSettings(rescue=False)


@dataclass(frozen=True)
class Scenario:
    """One realisation of the uncertainties: detuning e, force factor a, restitution shift r,
    the absorber's stiffness and damping off by the fractions k and c."""

    detuning: float = 0.0
    force: float = 1.0
    restitution: float = 0.0
    stiffness: float = 0.0
    damping: float = 0.0


@dataclass(frozen=True)
class Uncertainty:
    """What a designer does not know exactly (module docstring).

    Attributes
    ----------
    detuning : float
        The object's natural frequency within +-detuning (fraction).
    force : (float, float)
        The force amplitude between these factors of the design force.
    restitution : float
        R within +-restitution of the design's.
    stiffness, damping : float
        The absorber's spring c2 and damper within +-these fractions of the design's (both
        devices).
    """

    detuning: float = 0.1
    force: tuple = (0.5, 2.0)
    restitution: float = 0.15
    stiffness: float = 0.05
    damping: float = 0.2

    def axes(self) -> tuple:
        d, (a0, a1), r, k, c = self.detuning, self.force, self.restitution, self.stiffness, self.damping
        return (-d, 0.0, d), (a0, 1.0, a1), (-r, 0.0, r), (-k, 0.0, k), (-c, 0.0, c)

    def scenarios(self, criterion: str) -> list[Scenario]:
        """The scenarios of ``criterion`` (nominal first)."""
        es, fs, rs, ks, cs = self.axes()
        nominal = [Scenario()]
        if criterion in ("peak", "band_average"):
            return nominal
        if criterion == "detuning":
            return nominal + [Scenario(detuning=e) for e in es if e != 0.0]
        if criterion == "force":
            return nominal + [Scenario(force=a) for a in fs if a != 1.0]
        if criterion == "restitution":
            return nominal + [Scenario(restitution=r) for r in rs if r != 0.0]
        if criterion == "absorber":
            ends = [Scenario(stiffness=k) for k in ks if k != 0.0] + [Scenario(damping=c) for c in cs if c != 0.0]
            corners = [Scenario(stiffness=k, damping=c) for k, c in itertools.product(ks[::2], cs[::2])]
            return list(dict.fromkeys(nominal + ends + corners))
        if criterion == "together":
            ends = [s for c in ("detuning", "force", "restitution") for s in self.scenarios(c)[1:]]
            ends += [s for s in self.scenarios("absorber")[1:5]]
            box = itertools.product(es[::2], fs[::2], rs[::2], ks[::2], cs[::2])
            return list(dict.fromkeys(nominal + ends + [Scenario(*corner) for corner in box]))
        raise ValueError(f"`criterion` = {criterion!r} is not allowed: must be one of {', '.join(CRITERIA)}")

    def to_dict(self) -> dict:
        return {
            "detuning": self.detuning,
            "force": list(self.force),
            "restitution": self.restitution,
            "stiffness": self.stiffness,
            "damping": self.damping,
        }


def impact_parameters(mu: float, delta1: float, x: dict) -> Parameters:
    """The impact suppressor (gap, N, delta2, R of ``x``) on the object (mu, delta1)."""
    return Parameters(mu=mu, delta1=delta1, **{n: float(x[n]) for n in IMPACT_NAMES})


def _scenario_case(p: Parameters, band: tuple, s: Scenario) -> tuple[Parameters, tuple, float]:
    """The suppressor ``p`` in scenario ``s`` (module docstring): its relative parameters, the
    band in its theta, and the factor that puts its amplitudes over the nominal x_st per unit
    of the actual force."""
    f = 1.0 + s.detuning
    q = p.replace(
        N=p.N * math.sqrt(1.0 + s.stiffness) / f,
        delta1=p.delta1 / f,
        delta2=p.delta2 * (1.0 + s.damping) / f,
        gap=p.gap * f * f / s.force,
        R=min(max(p.R + s.restitution, R_LOW), R_HIGH) if s.restitution else p.R,
    )
    return q, (band[0] / f, band[1] / f), 1.0 / (f * f)


# How each fidelity of the search locates a peak: the grid alone with the closed-form floor
# (coarse); located to SEARCH_THETA_TOL; located to THETA_TOL with the random starts (final).
FIDELITY_OPTIONS = {
    "coarse": dict(theta_tol=1.0, random_count=0),
    "search": dict(theta_tol=SEARCH_THETA_TOL, random_count=0),
    "final": dict(theta_tol=THETA_TOL, random_count=RANDOM_COUNT),
}


class ImpactCriterion:
    """A criterion of the impact suppressor as the search evaluates it: ``(X, fidelity) ->
    values``, X rows (gap, N, delta2, R), all designs' scenarios in one batch of worst branches.
    With ``max_stroke`` a design over that stroke scores its criterion times (1 + STROKE_PENALTY
    x the relative excess) (the stroke is read at the ``search`` and ``final`` fidelities)."""

    def __init__(
        self,
        mu: float,
        delta1: float,
        band: tuple,
        criterion: str,
        uncertainty: Uncertainty,
        *,
        max_stroke: float | None = None,
        settings: SweepSettings = DESIGN_SETTINGS,
        workers: int = 1,
    ) -> None:
        self.mu, self.delta1, self.band, self.criterion = mu, delta1, band, criterion
        self.scenarios = uncertainty.scenarios(criterion)
        self.max_stroke, self.settings, self.workers = max_stroke, settings, workers

    def branches(self, designs: Sequence[dict], scenarios: Sequence[Scenario], fidelity: str) -> list:
        """The worst branches of every design in every scenario, (design, scenario) in order,
        each with its amplitude factor."""
        cases, bands, scales = [], [], []
        for x in designs:
            p = impact_parameters(self.mu, self.delta1, x)
            for s in scenarios:
                q, b, scale = _scenario_case(p, self.band, s)
                cases.append(q)
                bands.append(b)
                scales.append(scale)
        ws = worst_branches(cases, bands, settings=self.settings, workers=self.workers, **FIDELITY_OPTIONS[fidelity])
        return list(zip(ws, scales))

    def __call__(self, X: np.ndarray, fidelity: str) -> np.ndarray:
        designs = [dict(zip(IMPACT_NAMES, row)) for row in X]
        out = self.branches(designs, self.scenarios, fidelity)
        m = len(self.scenarios)
        values = []
        for i in range(len(designs)):
            mine = out[i * m : (i + 1) * m]
            if self.criterion == "band_average":
                v = mine[0][0].band_average
            else:
                v = max(scale * w.peak for w, scale in mine)
            if self.max_stroke is not None and fidelity != "coarse":
                stroke = _impact_stroke(mine[0][0])
                v *= 1.0 + STROKE_PENALTY * max(0.0, stroke / self.max_stroke - 1.0)
            values.append(v)
        return np.array(values)


def _tmd_peak(mu, delta1, N, delta2, band, s: Scenario) -> float:
    """The TMD's peak in scenario ``s`` over the nominal x_st (the force and the restitution
    change nothing)."""
    f = 1.0 + s.detuning
    dev = LinearDevice(mu, N * math.sqrt(1.0 + s.stiffness) / f, delta1 / f, delta2 * (1.0 + s.damping) / f)
    return float(dev.peak((band[0] / f, band[1] / f))[1]) / (f * f)


class TmdCriterion:
    """A criterion of the linear TMD in closed form, ``(X, fidelity) -> values`` (X rows (N,
    delta2); the fidelity changes nothing): its peak, its band average on the impact
    suppressor's grid, or its worst peak over the scenarios (the force and restitution leave a
    linear device unchanged). With ``max_stroke`` a design over it is penalised alike."""

    def __init__(
        self, mu: float, delta1: float, band: tuple, criterion: str, uncertainty: Uncertainty, *, max_stroke=None
    ):
        self.mu, self.delta1, self.band, self.criterion = mu, delta1, band, criterion
        scen = uncertainty.scenarios(criterion)
        self.scenarios = list(dict.fromkeys(Scenario(s.detuning, 1.0, 0.0, s.stiffness, s.damping) for s in scen))
        self.max_stroke = max_stroke
        self.thetas = np.linspace(band[0], band[1], band_points([band], STEP))

    def value(self, N: float, delta2: float) -> float:
        dev = LinearDevice(self.mu, N, self.delta1, delta2)
        if self.criterion == "band_average":
            v = dev.band_average(self.thetas)
        else:
            v = max(_tmd_peak(self.mu, self.delta1, N, delta2, self.band, s) for s in self.scenarios)
        if self.max_stroke is not None:
            v *= 1.0 + STROKE_PENALTY * max(0.0, dev.stroke_peak(self.band)[1] / self.max_stroke - 1.0)
        return v

    def __call__(self, X: np.ndarray, fidelity: str) -> np.ndarray:
        return np.array([self.value(float(N), float(d2)) for N, d2 in X])


def tmd_row(mu: float, delta1: float, band: tuple, x: dict, uncertainty: Uncertainty) -> dict:
    """A linear device's row of the design table (``x``: N, delta2; {} for the bare object)."""
    bare = not x
    dev = LinearDevice(0.0 if bare else mu, x.get("N", 1.0), delta1, x.get("delta2", 0.0))
    t, v = dev.peak(band)
    th = np.linspace(band[0], band[1], band_points([band], STEP))
    m, N, d2 = 0.0 if bare else mu, x.get("N", 1.0), x.get("delta2", 0.0)
    peaks = {Scenario(): float(v)}

    def peak(s: Scenario) -> float:  # (the force and the restitution change nothing)
        key = Scenario(s.detuning, 1.0, 0.0, s.stiffness, s.damping)
        if key not in peaks:
            peaks[key] = _tmd_peak(m, delta1, N, d2, band, key)
        return peaks[key]

    worst = {name: max(peak(s) for s in uncertainty.scenarios(name)) for name in ROBUST}
    return {
        "kind": "linear",
        "parameters": dict(x),
        "peak": float(v),
        "peak_theta": float(t),
        "peak_branch": "linear",
        "band_average": dev.band_average(th),
        "worst": {k: float(w) for k, w in worst.items()},
        "stroke": 0.0 if bare else float(dev.stroke_peak(band)[1]),
        "impacts": False,
    }


def impact_rows(
    mu: float,
    delta1: float,
    band: tuple,
    designs: Sequence[dict],
    uncertainty: Uncertainty,
    *,
    settings: SweepSettings = DESIGN_SETTINGS,
    workers: int = 1,
    stop_stiffness: float = STOP_STIFFNESS,
    natural_frequency: float = NATURAL_FREQUENCY,
    robust: Sequence[str] = ROBUST,
) -> list[dict]:
    """The design table's rows of impact suppressors: for each design its located worst branch
    (nominal), band average, worst peaks over each uncertainty and over all together (one batch
    of every design's scenarios, final fidelity; a design met twice is computed once), stroke
    and loads; ``robust``: the uncertainties evaluated (the others' worst peaks NaN)."""
    crit = ImpactCriterion(mu, delta1, band, "peak", uncertainty, settings=settings, workers=workers)
    scen = list(dict.fromkeys(s for name in ("peak", *robust) for s in uncertainty.scenarios(name)))
    distinct = list({tuple(x[n] for n in IMPACT_NAMES): x for x in designs}.values())
    out = crit.branches(distinct, scen, "final")
    mines = [dict(zip(scen, out[i * len(scen) : (i + 1) * len(scen)])) for i in range(len(distinct))]
    # Each design's loads run its grid's cycles afresh (pure Python, about a second each): one
    # design per process, whichever is free (the same numbers as one after the other).
    all_loads = map_blocks(
        lambda ws: [_impact_loads(w, stop_stiffness=stop_stiffness, natural_frequency=natural_frequency) for w in ws],
        [mine[Scenario()][0] for mine in mines],
        workers,
        dynamic=True,
    )
    rows = {}
    for x, mine, loads in zip(distinct, mines, all_loads):
        w = mine[Scenario()][0]
        worst = {}
        for name in ROBUST:
            worst[name] = (
                max(scale * v.peak for s, (v, scale) in mine.items() if s in uncertainty.scenarios(name))
                if name in robust
                else math.nan
            )
        rows[tuple(x[n] for n in IMPACT_NAMES)] = {
            "kind": "impact",
            "parameters": dict(x),
            "peak": w.peak,
            "peak_theta": w.peak_theta,
            "peak_branch": w.branch(),
            "grid_peak": w.grid_peak,
            "no_contact_floor": w.floor.value,
            "band_average": w.band_average,
            "worst": worst,
            "worst_scenarios": [
                {**vars(s), "peak": scale * v.peak, "theta": v.peak_theta} for s, (v, scale) in mine.items()
            ],
            "located_peaks": [q.to_dict() for q in w.peaks[:6]],
            **loads,
        }
    return [dict(rows[tuple(x[n] for n in IMPACT_NAMES)]) for x in designs]


def _cycle(p: Parameters, theta: float, section: np.ndarray, k: int, stop_stiffness: float) -> dict:
    """One settled cycle from its section (the front door's run), in relative units of its own
    theta (omega1 = omega/theta, P0 = c1 x_st): stroke, the largest pulse over P0/omega1, the
    mean force of the pulses over P0, impacts per period and the peak contact force over P0."""
    from impactdamper.analysis.solve import simulate

    q = p.replace(theta=float(theta))
    periods = k if k > 0 else NONPERIODIC_PERIODS
    end = periods * q.T
    traj = simulate(q, end, 0.0, np.array(section, float))
    full, _ = traj.sample(np.linspace(0.0, end, STROKE_SAMPLES * periods + 1))
    impacts = [e for e in traj.events if e.t < end and e.kind == "impact"]
    pulses = [abs(e.impulse) for e in traj.events if e.t < end and e.kind in ("impact", "stick")]
    omega1 = q.omega / q.theta
    P0 = q.P0
    m_red = q.m1 * q.m2 / (q.m1 + q.m2)
    velocity = max((abs(e.velocity) for e in impacts), default=0.0)
    return {
        "stroke": float(np.max(np.abs(full[:, 1] - full[:, 0]))) / q.x_st,
        "pulse": max(pulses, default=0.0) * omega1 / P0,
        "mean_force": float(sum(pulses)) / end / P0,
        "impacts_per_period": len(impacts) / periods,
        "contact_force": velocity * math.sqrt(stop_stiffness * q.c1 * m_red) / P0,
    }


def _cycles(w):
    """The grid's settled cycles of a worst branch: (theta, section, k) of the upward sweep at
    every theta, and of the downward one where it settled on another motion (max|x1| or k
    differ)."""
    same = (np.abs(w.up - w.down) <= 1e-9 * np.abs(w.up)) & (w.up_k == w.down_k)
    for sections, ks, skip in ((w.up_sections, w.up_k, np.zeros_like(same)), (w.down_sections, w.down_k, same)):
        for t, s, k, done in zip(w.thetas, sections, ks, skip):
            if not done and np.all(np.isfinite(s)):
                yield float(t), s, int(k)


def _impact_stroke(w) -> float:
    """max|x2 - x1|/x_st over the grid's settled cycles of a worst branch (:func:`_cycles`)."""
    return max((_cycle(w.p, t, s, k, STOP_STIFFNESS)["stroke"] for t, s, k in _cycles(w)), default=0.0)


def _impact_loads(w, *, stop_stiffness: float = STOP_STIFFNESS, natural_frequency: float = NATURAL_FREQUENCY) -> dict:
    """Stroke and loads of an impact suppressor over its band grid, both sweep directions (each
    grid point's settled cycle run afresh from its section; ``w`` a
    :class:`~impactdamper.analysis.peaks.WorstBranch`).

    Returns
    -------
    dict
        ``stroke`` max|x2 - x1|/x_st; ``pulse`` the largest pulse S per impact over P0/omega1;
        ``mean_force`` the largest mean force of the pulses over P0; ``impacts_per_period`` the
        most; ``impacts_per_hour`` the most per hour with the object's natural frequency
        ``natural_frequency`` Hz (impacts per period x theta x f1 x 3600); ``contact_force``
        the largest peak force over P0 of a linear spring stop of stiffness ``stop_stiffness``
        c1: the elastic contact of the reduced mass m_red = m1 m2/(m1 + m2) at the closing
        velocity v peaks at v sqrt(k_c m_red) (a stiffer stop, a larger force; damping in the
        contact lowers it); ``impacts`` whether any cycle impacts; ``stop_stiffness``,
        ``natural_frequency``.
    """
    keys = ("stroke", "pulse", "mean_force", "impacts_per_period", "impacts_per_hour", "contact_force")
    best = dict.fromkeys(keys, 0.0)
    for t, s, k in _cycles(w):
        c = _cycle(w.p, t, s, k, stop_stiffness)
        c["impacts_per_hour"] = c["impacts_per_period"] * t * natural_frequency * 3600.0
        for key in keys:
            best[key] = max(best[key], float(c[key]))
    return {
        **best,
        "impacts": best["impacts_per_period"] > 0,
        "stop_stiffness": stop_stiffness,
        "natural_frequency": natural_frequency,
    }
