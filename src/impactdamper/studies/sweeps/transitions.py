"""Where the motion changes along the gap sweep: the transitions between the sweep's labels
and the three with analytic values, each checked a second, independent way.

Extends Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100.
``workflow/scripts/sweep_transitions.py`` runs it on the sweep's points and writes the records.
2. Three transitions have analytic values. (a) and (b) are located a second time with every
   point simulated (no closed form, no orbit continuation: ``continuation=False``), to
   ``check_xtol``, so the check is independent of the formula; (c) as said below:

   (a) lift-off of the persistent contact, upward from ``stuck``: the contact force
       F = -m2 x1'' - c2 Delta0 of the joined bodies' forced response first reaches zero at
       Delta0/x_st = -(theta/N)^2/|1 - (1 + mu) theta^2 + 2 i delta1 theta|
       (:func:`impactdamper.analysis.transitions.stuck_liftoff_gap`);
   (b) first contact, downward from ``0/1``: the free forced response reaches the stop when
       Delta0 falls below U1 = |x2p_hat - x1p_hat| (eq. 12, :func:`~impactdamper.analysis.transitions.no_contact_gap`);
   (c) Algorithm No. 1's orbit starts to cross the stop between impacts (its interior gap
       minimum reaches zero; bisection on its admissibility,
       :func:`~impactdamper.analysis.transitions.algorithm1_grazing_gap`), against where the downward sweep's
       one-impact motion 1/1 ends -- located by the sweep's own bisection (orbit continuation),
       since from a neighbour's state at a finite step a plain simulation can leave the shrinking
       basin of the one-impact orbit early; a simulation started on the orbit itself confirms
       that it is the settled motion just above the grazing and not just below.

   Each analytic value is also computed numerically a second way: (a) the least contact force
   over a sampled and refined period of the model's own contact-force functional, root-found in
   the gap; (b) the largest x2p - x1p of the free mode's forced response, sampled and refined;
   (c) a root of Algorithm No. 1's interior gap minimum in the gap (brentq), and the grazing
   point found by pseudo-arclength continuation of the orbit (:mod:`impactdamper.analysis.orbits`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import scipy.optimize

from impactdamper import algorithm1
from impactdamper.analysis.continuation import continue_orbit
from impactdamper.analysis.orbits import OrbitError, solve_orbit
from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.sweeps import locate_transition, with_value
from impactdamper.analysis.transitions import algorithm1_grazing_gap, no_contact_gap, stuck_liftoff_gap
from impactdamper.core.linear import free_mode
from impactdamper.core.model import Model

__all__ = [
    "EXTREMUM_SAMPLES",
    "SIMULATION_OFFSET",
    "FINITE_STEP_NOTE",
    "first_contact_check",
    "checks",
]

# Samples per period before refining an extremum of a periodic function of time.
EXTREMUM_SAMPLES = 2048


def _extremum(f, T: float, sign: float) -> float:
    """max (sign = 1) or min (sign = -1) of a T-periodic f over a period: samples, then refined."""
    ts = np.linspace(0.0, T, EXTREMUM_SAMPLES, endpoint=False)
    vals = np.array([sign * f(t) for t in ts])
    i = int(np.argmax(vals))
    res = scipy.optimize.minimize_scalar(
        lambda t: -sign * f(t),
        bounds=(ts[i] - T / EXTREMUM_SAMPLES, ts[i] + T / EXTREMUM_SAMPLES),
        method="bounded",
        options={"xatol": 1e-14 * T},
    )
    return sign * max(vals[i], -float(res.fun))


def _least_contact_force(p) -> float:
    """min over a period of the contact force of the joined bodies' forced response, relative."""
    model = Model(p)
    mode, fn = model.stuck, model.contact_force
    return _extremum(lambda t: float(fn.of_state(t, mode.forced(t))), p.T, -1.0) / model.force_scale


def _largest_relative_displacement(p) -> float:
    """max over a period of x2p - x1p of the free mode's forced response, over x_st."""
    mode = free_mode(p)
    return _extremum(lambda t: float(mode.forced(t)[1] - mode.forced(t)[0]), p.T, 1.0) / p.x_st


# Distance from the grazing at which the simulation check starts on Algorithm No. 1's orbit.
SIMULATION_OFFSET = 1e-4
FINITE_STEP_NOTE = (
    "with every point simulated from its neighbour's state, the downward sweep leaves 1/1 "
    "a little above the grazing (the one-impact orbit's basin shrinks as its gap minimum "
    "approaches zero)"
)


def _settles_on_alg1(base, gap: float, settings) -> str:
    """Label of the motion simulated from Algorithm No. 1's orbit (state 1e-9 x_st off it)."""
    p = with_value(base, "gap", gap)
    a = algorithm1(p)
    if not a.exists:
        return "no orbit"
    state = a.sample(np.array([p.T - a.t_impact]))[0]  # at t = T (phase 0), inside the flight
    state = state + np.array([1e-9, 0.0, 0.0, 0.0]) * p.x_st
    return solve_point(p, gap, state=state, settings=replace(settings, continuation=False)).label


# The record's words for each check: what the transition is, and how the sweep locates it.
DESCRIPTION = {
    "liftoff": "persistent contact lifts off (upward sweep leaves stuck)",
    "first_contact": "free forced response reaches the stop (downward sweep leaves 0/1)",
    "alg1_grazing": "Algorithm No. 1's orbit starts to cross the stop between impacts (downward sweep's 1/1 ends)",
}
LOCATED_BY = {
    "liftoff": "simulation bisection from the stuck motion",
    "first_contact": "simulation bisection from the no-contact motion",
    "alg1_grazing": "sweep bisection (orbit continuation) from the one-impact motion",
}


def _run(points, label_ok, after: bool):
    """Index pairs (i, i+1) in sweep order where a run of labels satisfying label_ok ends."""
    for i in range(len(points) - 1):
        if label_ok(points[i]) and not label_ok(points[i + 1]):
            return i
    return None


def _check(name, analytic, numeric, located, bracket):
    """One check; ``located_bracket`` is [lower, upper, label before, label after, stopped early]."""
    return {
        "name": name,
        "description": DESCRIPTION[name],
        "analytic": analytic,
        "numeric": numeric,
        "located": located,
        "located_bracket": bracket,
        "located_method": LOCATED_BY[name],
        "analytic_minus_numeric": None if numeric is None else analytic - numeric,
        "analytic_minus_located": None if located is None else analytic - located,
    }


def _bracket(tr) -> list:
    """A located transition's bisection bracket, as a check records it."""
    return [tr.lower, tr.upper, tr.before, tr.after, tr.stopped]


def _run_end(base, parameter: str, points, label: str, direction: str, settings, xtol: float):
    """Where the first run of motions labelled ``label`` ends along ``points`` (in the sweep's
    ``direction``), bisected by simulation: (located value, :func:`_bracket`), or (None, None)
    where no such run ends."""
    i = _run(points, lambda p: p.label == label, True)
    if i is None:
        return None, None
    tr = locate_transition(base, parameter, points[i], points[i + 1], direction, settings=settings, xtol=xtol)
    return tr.value, _bracket(tr)


def _liftoff_check(base, parameter: str, up, settings, xtol: float) -> dict:
    """(a) Lift-off of the persistent contact (the upward sweep leaves "stuck"): the closed form,
    the root of the joined bodies' least contact force, and the sweep's simulation bisection."""
    analytic = stuck_liftoff_gap(base)
    numeric = scipy.optimize.brentq(
        lambda g: _least_contact_force(with_value(base, "gap", g)),
        analytic - 1.0,
        analytic + 1.0,
        xtol=1e-14,
        rtol=1e-15,
    )
    return _check("liftoff", analytic, numeric, *_run_end(base, parameter, up, "stuck", "up", settings, xtol))


def first_contact_check(base, parameter: str, down, settings, xtol: float) -> dict:
    """(b) First contact (the downward sweep leaves "0/1"): U1 of eq. (12), the free forced
    response's largest relative displacement, and the sweep's simulation bisection."""
    analytic = no_contact_gap(base)
    numeric = _largest_relative_displacement(base)
    located = _run_end(base, parameter, down[::-1], "0/1", "down", settings, xtol)
    return _check("first_contact", analytic, numeric, *located)


def _alg1_grazing_check(base, parameter: str, down, settings, xtol: float) -> dict:
    """(c) Algorithm No. 1's orbit starts to cross the stop between impacts, bracketed from the
    stated gap downward: the closed form, the root of the orbit's least gap, the orbit
    continuation's grazing, the sweep's bisection, and simulations started on the orbit on
    either side."""
    g0 = float(base.gap)
    rdown = down[::-1]
    values = sorted(p.value for p in down)
    below = [v for v in values if v <= g0][::-1]
    adm = [bool(algorithm1(with_value(base, "gap", v)).admissible) for v in below]
    analytic = numeric = located = bracket = None
    extra = {}
    if adm and adm[0] and not all(adm):
        j = adm.index(False)
        analytic = algorithm1_grazing_gap(base, (below[j - 1], below[j]), xtol=1e-12)
        try:
            numeric = scipy.optimize.brentq(
                lambda g: algorithm1(with_value(base, "gap", g)).min_gap,
                analytic + 0.05,
                analytic - 0.05,
                xtol=1e-14,
                rtol=1e-15,
            )
        except ValueError:
            numeric = None
        try:
            with np.errstate(over="ignore", invalid="ignore"):
                o = solve_orbit(base, "alg1")
                br = continue_orbit(o, "gap", (below[j] - 1.0, g0), direction=-1)
            graze = [s.value for s in br.special if s.kind == "grazing_interior"]
            extra["continuation"] = graze[0] if graze else None
        except (OrbitError, ValueError):
            extra["continuation"] = None
        # The downward sweep's one-impact motion containing the stated gap: where it ends, by
        # the sweep's own bisection (orbit continuation). A plain simulation from the
        # neighbour's state is not used here: near the grazing the one-impact orbit's basin
        # shrinks, and a finite step can throw the motion onto the coexisting 4/3 motion a
        # little before the orbit ends (see FINITE_STEP_NOTE).
        i0 = min(range(len(rdown)), key=lambda i: abs(rdown[i].value - g0))
        k = i0
        while k + 1 < len(rdown) and rdown[k + 1].label == rdown[i0].label:
            k += 1
        if rdown[i0].label == "1/1" and k + 1 < len(rdown):
            tr = locate_transition(base, parameter, rdown[k], rdown[k + 1], "down", settings=settings, xtol=xtol)
            located, bracket = tr.value, _bracket(tr)
        # Simulation confirms: started on Algorithm No. 1's orbit (perturbed by 1e-9) just
        # above the grazing it settles on 1/1; just below, the orbit crosses the stop.
        extra["simulation_above"] = _settles_on_alg1(base, analytic + SIMULATION_OFFSET, settings)
        extra["simulation_below"] = _settles_on_alg1(base, analytic - SIMULATION_OFFSET, settings)
    c = _check("alg1_grazing", analytic, numeric, located, bracket)
    c.update(extra)
    c["note"] = FINITE_STEP_NOTE
    return c


def checks(base, parameter: str, up, down, settings, xtol: float, log=None) -> list[dict]:
    """The three transitions with analytic values (see the module docstring), each against its
    numeric value and where the sweep locates it (``up``, ``down``: the sweep's points;
    ``xtol``: the bisection's tolerance in Delta0/x_st): :func:`liftoff_check` and
    :func:`first_contact_check` by simulation alone, :func:`alg1_grazing_check` by the sweep's
    own bisection."""
    sim = replace(settings, continuation=False)
    out = [_liftoff_check(base, parameter, up, sim, xtol)]
    if log is not None:
        c = out[-1]
        log.info("(a) analytic %.12g numeric %.12g located %s", c["analytic"], c["numeric"], c["located"])
    out.append(first_contact_check(base, parameter, down, sim, xtol))
    if log is not None:
        c = out[-1]
        log.info("(b) analytic %.12g numeric %.12g located %s", c["analytic"], c["numeric"], c["located"])
    out.append(_alg1_grazing_check(base, parameter, down, settings, xtol))
    if log is not None:
        c = out[-1]
        log.info(
            "(c) analytic %s numeric %s located %s continuation %s",
            c["analytic"],
            c["numeric"],
            c["located"],
            c.get("continuation"),
        )
    return out
