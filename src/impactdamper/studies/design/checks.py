"""The located worst branch checked three independent ways (the design stage's check record).

The worst branch (:func:`impactdamper.analysis.peaks.worst_branches`) is checked for a few
suppressors (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100; Algorithm No. 2 with
the impact law of eqs. 21-22) against

* **slow sweeps**: both directions on a grid ten times finer (step ``FINE_STEP``), each point
  from its neighbour's settled motion: no sample may exceed the located peak (beyond
  ``SAMPLE_RTOL``), and their largest sample falls short of the sweeps' highest located
  maximum by what its step allows (the floor, where higher, is a motion the sweeps from the
  band's ends do not follow);
* **the closed form** of the motion without contact: at the floor's first contact the linear
  relative amplitude U1 (eq. 12, :func:`impactdamper.analysis.transitions.no_contact_gap`, by a
  complex matrix solve of eq. 10 rather than the polynomials the floor uses) equals the gap, and
  |x1_hat| there is the floor's value;
* **an independent solver**: the located peak's settled motion integrated again by
  ``solve_ivp`` (:func:`impactdamper.baselines.ivp.simulate_ivp`, DOP853 at 1e-11) over one
  cycle, its largest |x1| sampled densely.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from impactdamper.analysis.batch import steady_states
from impactdamper.analysis.peak_location import NAMES
from impactdamper.analysis.peaks import THETA_TOL, WorstBranch, worst_branches
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.transitions import no_contact_gap
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.parameters import Parameters
from impactdamper.studies.design.devices import IMPACT_NAMES

__all__ = ["FINE_STEP", "SAMPLE_RTOL", "located_peak_checks"]

# The slow sweeps' step: ten times finer than the worst branch's grid.
FINE_STEP = 0.002
# A slow sweep's sample above the located peak by more than this (relative) is a miss: the
# located values hold to the settle tolerance's effect on max|x1| (~1e-9) where smooth.
SAMPLE_RTOL = 1e-6
# Samples per forcing period of the solve_ivp check's max|x1| (the maximum is smooth: the
# sampling error is ~(pi/SAMPLES)^2/2 ~ 1e-9).
IVP_SAMPLES = 50_000


def _fine_sweeps(p: Parameters, band: tuple, settings: SweepSettings, step: float = FINE_STEP) -> dict:
    """Both slow sweeps of ``p`` over ``band`` at ``step``: their largest sample and where."""
    n = int(math.ceil((band[1] - band[0]) / step - 1e-9)) + 1
    th = np.linspace(band[0], band[1], n)
    rows = [[t if k == "theta" else getattr(p, k) for k in NAMES] for t in np.r_[th, th[::-1]]]
    res = steady_states(p, NAMES, np.array(rows), settings=settings, chain_length=n)
    y = np.asarray(res.x1_max, float)
    i = int(np.nanargmax(y))
    return {"largest": float(y[i]), "theta": float(res.values[i, 0]), "points": int(2 * n)}


def _floor_check(w: WorstBranch) -> dict | None:
    """The floor's first contact against eq. 10 solved as a matrix (module docstring); None
    where the floor's largest value is not at a first contact."""
    f = w.floor
    if not f.first_contact:
        return None
    q = w.p.replace(theta=f.theta)
    x1, _ = forced_amplitudes(q)
    return {
        "theta": f.theta,
        "gap_difference": abs(no_contact_gap(q) - w.p.gap) / abs(w.p.gap),
        "value_difference": abs(abs(x1) / q.x_st - f.value) / f.value,
    }


def _swept_peak(w: WorstBranch) -> float:
    """The largest located maximum of the two sweeps (not the floor, not a random start)."""
    return max((q.value for q in w.peaks if q.source in ("up", "down")), default=math.nan)


def _ivp_peak(w: WorstBranch, settings: SweepSettings) -> dict | None:
    """The sweeps' highest located maximum's motion integrated again by solve_ivp (module
    docstring); None where it did not settle."""
    from impactdamper.baselines.ivp import simulate_ivp

    swept = [q for q in w.peaks if q.source in ("up", "down")]
    if not swept or swept[0].label in ("np", "failed"):
        return None
    top = swept[0]
    up = top.source == "up"
    th = w.thetas if up else w.thetas[::-1]
    sections = w.up_sections if up else w.down_sections[::-1]
    before = np.flatnonzero((th <= top.theta) if up else (th >= top.theta))
    if not len(before):
        return None
    j = int(before[-1])
    ts = th[j] + (top.theta - th[j]) * np.arange(1, 9) / 8
    rows = [[t if k == "theta" else getattr(w.p, k) for k in NAMES] for t in ts]
    res = steady_states(w.p, NAMES, np.array(rows), settings=settings, chain_length=8, states=sections[j][None, :])
    k = int(res.period_multiple[-1])
    if k <= 0:
        return None
    q = w.p.replace(theta=float(ts[-1]))
    times = np.linspace(0.0, k * q.T, IVP_SAMPLES * k + 1)
    traj = simulate_ivp(q, k * q.T, 0.0, res.sections[-1], rtol=1e-11, atol=1e-13 * q.x_st, sample_times=times)
    x1 = float(np.max(np.abs(traj.samples[:, 0]))) / q.x_st
    return {
        "theta": float(ts[-1]),
        "located": float(res.x1_max[-1]),
        "ivp": x1,
        "difference": abs(x1 / res.x1_max[-1] - 1),
    }


def located_peak_checks(cases: Sequence[tuple[str, Parameters]], band: tuple, settings: SweepSettings) -> dict:
    """The checks of the module docstring for each (name, suppressor) of ``cases``.

    Returns
    -------
    dict
        ``cases`` (per case: the located peak and its branch, the sweeps' highest located
        maximum, the slow sweeps' largest sample, the floor and solve_ivp checks), the largest
        ``fine_largest_excess`` (a slow sweep's sample above the located peak, relative; <= 0
        where none is above) and ``fine_largest_shortfall`` (below the sweeps' located
        maximum), ``floor_largest_difference``, ``ivp_largest_difference``, ``ivp_count``,
        ``fine_step``, ``theta_tol``.
    """
    ws = worst_branches([p for _, p in cases], [band] * len(cases), theta_tol=THETA_TOL, settings=settings)
    out, excess, shortfall, floors, ivps = {}, [], [], [], []
    for (name, p), w in zip(cases, ws):
        fine = _fine_sweeps(p, band, settings)
        fl, iv = _floor_check(w), _ivp_peak(w, settings)
        excess.append(fine["largest"] / w.peak - 1.0)
        shortfall.append(1.0 - fine["largest"] / _swept_peak(w))
        if fl is not None:
            floors.append(max(fl["gap_difference"], fl["value_difference"]))
        if iv is not None:
            ivps.append(iv["difference"])
        out[name] = {
            "parameters": {k: getattr(p, k) for k in ("mu", "delta1", *IMPACT_NAMES)},
            **w.to_dict(),
            "swept_peak": _swept_peak(w),
            "fine": fine,
            "floor_check": fl,
            "ivp_check": iv,
        }
    return {
        "cases": out,
        "cases_count": len(cases),
        "fine_step": FINE_STEP,
        "theta_tol": THETA_TOL,
        "sample_rtol": SAMPLE_RTOL,
        "fine_largest_excess": max(excess),
        "fine_largest_shortfall": max(shortfall),
        "floor_largest_difference": max(floors, default=math.nan),
        "ivp_largest_difference": max(ivps, default=math.nan),
        "ivp_count": len(ivps),
    }
