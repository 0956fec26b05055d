"""The replication's independent cross-checks: Algorithms No. 1 and No. 2 of Timofeev,
Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100, integrated again by
``solve_ivp`` (:mod:`impactdamper.baselines.ivp`), and each compared with the exact solver:
Algorithm No. 1's orbit by its periodicity residual and the ends of its negative-gap intervals
(the paper's Fig. 2a), Algorithm No. 2's settled cycle impact by impact, aligned by forcing
phase (the paper's Fig. 2b, :func:`impactdamper.studies.replication.claims.compare_cycles`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.integrate
import scipy.optimize

from impactdamper import Parameters, Tolerances
from impactdamper.baselines.ivp import simulate_ivp
from impactdamper.core.model import Model
from impactdamper.core.parameters import state_scale
from impactdamper.studies.config import steady_options
from impactdamper.studies.replication.claims import CLAIM_B_IMPACTS, CLAIM_B_PERIOD_MULTIPLE, compare_cycles

__all__ = [
    "IVP_GAP_SAMPLES",
    "free_rhs",
    "gap_sign_scan",
    "alg1_ivp",
    "alg2_ivp",
    "ivp_options",
    "alg2_crosscheck",
    "compare_alg1",
]

# Grid of the independent gap scan of an Algorithm No. 1 orbit (per period): the solve_ivp
# dense output is sampled there and every sign change refined by brentq.
IVP_GAP_SAMPLES = 4000
# Absolute tolerance (units of T) of a refined sign change of the gap: far below the
# cross-check's tolerance on the interval ends (config verdict), near rounding of t/T ~ 1.
GAP_ROOT_XTOL = 1e-14


def free_rhs(p: Parameters):
    """The right-hand side of eqs. (2) + (9) without the stop, f(t, y) with y = (x1, x2, x1',
    x2'): the independent integrator's own definition
    (:mod:`impactdamper.baselines.ivp`), so that it is written once."""
    from impactdamper.baselines.ivp import Equations

    return Equations(p).free_rhs


@dataclass(frozen=True)
class _GapScan:
    """The gap's sign over one period, from a sampled and refined scan (:func:`gap_sign_scan`).

    Attributes
    ----------
    samples : ndarray, shape (n - 1,)
        The gap at the interior sample points s = 1/n, ..., (n-1)/n of the period, m.
    crossings : tuple of float
        Its sign changes in units of the period, each refined by Brent's method.
    negative_intervals : tuple of (float, float)
        Where the gap is negative, in units of the period (0 and 1 where it is negative at an
        end of the scan).
    """

    samples: np.ndarray
    crossings: tuple
    negative_intervals: tuple

    @property
    def interior_minima(self) -> list[float]:
        """The gap at the samples' interior local minima, m."""
        g = self.samples
        return [float(g[i]) for i in np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] <= g[2:])) + 1]


def gap_sign_scan(gap_of, samples: int, xtol: float = GAP_ROOT_XTOL) -> _GapScan:
    """Scan ``gap_of(s)`` (the gap at s periods after an impact, s in (0, 1)) at ``samples``
    intervals strictly inside the period; refine every sign change by Brent's method to
    ``xtol``. The sign of the gap Delta = Delta0 - (x2 - x1) is the paper's Fig. 2a test."""
    tau = np.linspace(0.0, 1.0, int(samples) + 1)[1:-1]  # strictly inside the period
    g = np.array([float(gap_of(s)) for s in tau])
    crossings = tuple(
        float(scipy.optimize.brentq(gap_of, tau[i], tau[i + 1], xtol=xtol))
        for i in np.flatnonzero(np.sign(g[1:]) != np.sign(g[:-1]))
    )
    edges = ([0.0] if g[0] < 0 else []) + list(crossings) + ([1.0] if g[-1] < 0 else [])
    return _GapScan(
        samples=g, crossings=crossings, negative_intervals=tuple((lo, hi) for lo, hi in zip(edges[0::2], edges[1::2]))
    )


def alg1_ivp(a, method: str = "DOP853", rtol: float = 1e-10, atol: float = 1e-10) -> dict:
    """Check an Algorithm No. 1 orbit with ``solve_ivp``: integrate eqs. (2) + (9) (no stop)
    from the state just after the impact over one period T, then

    * apply the impact law (eqs. 21-22) to the state reached at T and compare with the start
      (the orbit is periodic only if they agree): ``periodicity_residual``, relative to x_st
      and x_st omega;
    * read the gap's sign over the period from the dense output: negative intervals (units of
      T since the impact) and the smallest interior local minimum of the gap.
    """
    p = a.p
    t0 = a.t_impact
    sol = scipy.integrate.solve_ivp(
        free_rhs(p), (t0, t0 + p.T), a.state_after, method=method, rtol=rtol, atol=atol, dense_output=True
    )
    before = sol.y[:, -1]
    v = before[3] - before[2]
    end, _, _ = Model(p).impact(before)
    scale = state_scale(p)
    residual = float(np.max(np.abs(end - a.state_after) / scale))

    def gap(s):  # the gap s periods after the impact, m
        y = sol.sol(t0 + s * p.T)
        return p.Delta0 - (y[1] - y[0])

    scan = gap_sign_scan(gap, IVP_GAP_SAMPLES)
    minima = scan.interior_minima
    return {
        "method": method,
        "rtol": rtol,
        "atol": atol,
        "periodicity_residual": residual,
        "closing_velocity": float(v),
        # As Algorithm1Result.min_gap: the smallest interior local minimum of the gap (0 when
        # the gap has none, i.e. it only rises from the impact and falls to the next one).
        "min_gap": float(min(minima) / p.x_st) if minima else 0.0,
        "negative_gap_intervals": [list(iv) for iv in scan.negative_intervals],
        "claim_a": bool(scan.negative_intervals),
    }


def _sections(traj, p: Parameters, t0: float, n: int) -> np.ndarray:
    """The run's states at t0 + i T, i = 0..n, relative: as it recorded them (its
    ``sample_times``), else from its legs integrated again with dense output."""
    times = t0 + p.T * np.arange(n + 1)
    if np.array_equal(traj.sample_times, times) and np.all(np.isfinite(traj.samples)):
        full = traj.samples
    else:
        full, _ = traj.sample(times)
    return full / state_scale(p)


def alg2_ivp(
    p: Parameters,
    periods: int,
    kmax: int,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-10,
    section_tol: float = 1e-6,
    exact=None,
    state=None,
    t0: float = 0.0,
    tolerances: Tolerances | None = None,
    time_tol: float = 1e-8,
    velocity_tol: float = 1e-8,
) -> dict:
    """Run Algorithm No. 2 with the independent ``solve_ivp`` integrator
    (:func:`impactdamper.baselines.ivp.simulate_ivp`) for ``periods`` forcing periods from the
    paper's step 1 (or ``state`` at ``t0``) and read the settled motion off its own
    stroboscopic sections: the smallest k <= kmax whose last k sections repeat the ones k
    periods earlier within ``section_tol`` (relative), and the impacts in the last k periods.

    With ``exact`` (a :class:`impactdamper.SteadyState` of the same start), also compares the
    two settled cycles aligned by forcing phase (:func:`~impactdamper.studies.replication.claims.compare_cycles`):
    the exact solver describes its cycle on a fresh run whose clock differs from this run's by
    whole periods, so impacts are paired by t/T modulo k, never by absolute time or by counts
    alone. ``agree`` is both differences within ``time_tol`` (units of T) and
    ``velocity_tol`` (relative to x_st omega).
    """
    t_end = t0 + (periods + 1) * p.T
    traj = simulate_ivp(
        p,
        t_end,
        t0=t0,
        state=state,
        method=method,
        rtol=rtol,
        atol=atol,
        tolerances=tolerances,
        sample_times=t0 + p.T * np.arange(periods + 1),
    )
    sec = _sections(traj, p, t0, periods)
    k_found, mismatch = 0, math.inf
    for k in range(1, kmax + 1):
        if len(sec) < 2 * k + 1:
            break
        worst = float(np.max(np.abs(sec[-k:] - sec[-2 * k : -k])))
        mismatch = min(mismatch, worst)
        if worst < section_tol:
            k_found, mismatch = k, worst
            break
    window = (t0 + (periods - max(k_found, 1)) * p.T, t0 + periods * p.T)
    impacts = traj.impacts(*window)
    contact = any(e.kind in ("stick", "liftoff") for e in traj.events if window[0] <= e.t < window[1])
    out = {
        "method": method,
        "rtol": rtol,
        "atol": atol,
        "periods": periods,
        "period_multiple": k_found,
        "impacts_per_cycle": len(impacts) if k_found else None,
        "contact_in_cycle": contact,
        "section_mismatch": mismatch,
        "claim_b": bool(k_found == CLAIM_B_PERIOD_MULTIPLE and len(impacts) == CLAIM_B_IMPACTS and not contact),
        "nfev": traj.nfev,
    }
    if exact is not None:
        cmp = compare_cycles(
            exact.impacts, exact.period_multiple, impacts, k_found, p.T, p.x_st * p.omega, time_tol, velocity_tol
        )
        out["cycle_comparison"] = {key: value for key, value in cmp.to_dict().items() if key != "pairs"}
        out["cycle_comparison"]["pairs_time_over_T_velocity_rel"] = cmp.pairs
        out["max_time_difference_over_T"] = cmp.max_time_difference_over_T
        out["max_velocity_difference_rel"] = cmp.max_velocity_difference_rel
        out["agree"] = cmp.agree
    return out


def ivp_options(verdict: dict) -> dict:
    """The ``solve_ivp`` method and tolerances of the verdict's cross-checks (config ``verdict``:
    ``ivp_method``, ``ivp_rtol``, ``ivp_atol``), as :func:`alg1_ivp` and :func:`alg2_ivp` take them."""
    return dict(method=verdict["ivp_method"], rtol=float(verdict["ivp_rtol"]), atol=float(verdict["ivp_atol"]))


def alg2_crosscheck(p: Parameters, exact, verdict: dict, solver: dict, *, state=None, t0: float = 0.0) -> dict:
    """:func:`alg2_ivp` as the verdict's cross-check runs it against the exact settled motion
    ``exact`` of the same start (``state`` at ``t0``; default the paper's step 1): the verdict's
    ``solve_ivp`` options (:func:`ivp_options`), section tolerance and cycle tolerances
    (``crosscheck_time_tol``, ``crosscheck_velocity_tol``), the solver's tolerances and
    ``max_period_multiple`` (kmax), over the exact run's periods and kmax more."""
    kmax = int(solver["max_period_multiple"])
    return alg2_ivp(
        p,
        exact.periods + kmax,
        kmax,
        section_tol=float(verdict["ivp_section_tol"]),
        exact=exact,
        state=state,
        t0=t0,
        tolerances=steady_options(solver)["tolerances"],
        time_tol=float(verdict["crosscheck_time_tol"]),
        velocity_tol=float(verdict["crosscheck_velocity_tol"]),
        **ivp_options(verdict),
    )


def compare_alg1(a, ivp: dict, time_tol: float, residual_tol: float) -> dict:
    """Algorithm No. 1's orbit against its ``solve_ivp`` re-integration (:func:`alg1_ivp`):
    the periodicity residual must be within ``residual_tol`` and every end of the negative-gap
    intervals within ``time_tol`` (units of T) of the exact one; a different number of
    intervals never agrees."""
    if not a.exists:
        return {
            "agree": not ivp.get("claim_a", False),
            "reason": "no orbit: nothing to integrate",
            "max_interval_end_difference_over_T": None,
            "periodicity_residual": None,
            "time_tol": time_tol,
            "residual_tol": residual_tol,
        }
    ex, iv = a.negative_gap_intervals, ivp["negative_gap_intervals"]
    residual = ivp["periodicity_residual"]
    if len(ex) != len(iv):
        diff, reason = math.inf, f"different numbers of negative-gap intervals: {len(ex)} and {len(iv)}"
    else:
        diff = max((abs(x - y) for e, i in zip(ex, iv) for x, y in zip(e, i)), default=0.0)
        reason = "" if diff <= time_tol else f"interval ends differ by {diff:.1e} T > {time_tol:.0e}"
    if residual > residual_tol:
        reason = (reason + "; " if reason else "") + f"periodicity residual {residual:.1e} > {residual_tol:.0e}"
    return {
        "agree": not reason,
        "reason": reason,
        "max_interval_end_difference_over_T": diff,
        "periodicity_residual": residual,
        "time_tol": time_tol,
        "residual_tol": residual_tol,
    }
