"""Tests of :mod:`impactdamper.analysis.curves`: each augmented system on a case with a known
answer. Closed forms first (first contact: the free response's U1; the fold of the one-impact
orbit: the existence limit of eq. 16), then Algorithm No. 1's bisected grazing, a period
doubling bisected by brute-force simulation, and the curves' crossings of the reference theta
against the one-parameter table (figures/orbit_special_points.csv), seeded away from it."""

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from impactdamper import solve_orbit, steady_state
from impactdamper.analysis.continuation import continue_orbit
from impactdamper.analysis.curves import CODIM2_REASONS, END_REASONS, curve_point, follow_curve
from impactdamper.analysis.shooting import Shooting
from impactdamper.analysis.transitions import algorithm1_existence_gap, algorithm1_grazing_gap, no_contact_gap
from impactdamper.core.events import Segment
from impactdamper.core.model import Model
from impactdamper.core.parameters import Parameters

ROOT = Path(__file__).resolve().parents[2]
PLANE = (("gap", "theta"), ((-40.0, 15.0), (0.9, 1.1)))


def reference(**changes) -> Parameters:
    return Parameters(theta=1.0, mu=0.08, N=0.5, delta1=0.05, delta2=0.05, R=0.7, gap=-5.8).replace(**changes)


def special_points(p: Parameters, bounds) -> dict:
    """The one-impact branch's special points from Algorithm No. 1's orbit at p, both ways."""
    o = solve_orbit(p, "alg1")
    found = {}
    for direction, bb in ((-1, (bounds[0], p.gap)), (+1, (p.gap, bounds[1]))):
        b = continue_orbit(o, "gap", bb, direction=direction, stop_at_grazing=False)
        for s in b.special:
            found.setdefault((s.kind, direction), s)
    return found


@pytest.fixture(scope="module")
def one_impact():
    return special_points(reference(), (-12.5, 11.6))


def curve(p, sp, k=1, plane=PLANE, **kw):
    return follow_curve(p.replace(gap=sp.value), k, sp.point.times, sp.point.states_after, sp.kind, *plane, **kw)


def test_grazing_velocity_curve_is_the_first_contact_closed_form(one_impact):
    # Zero closing velocity of the 1/1 cycle: the free response just touches the stop, Delta0 = U1.
    c = curve(reference(), one_impact[("grazing_velocity", +1)], plane=(("gap", "theta"), ((-40.0, 15.0), (0.5, 1.5))))
    err = max(abs(a - no_contact_gap(reference(theta=b))) for a, b in c.points)
    assert err <= 1e-8, err
    assert len(c.points) > 50 and c.points[:, 1].min() == 0.5 and c.points[:, 1].max() == 1.5
    assert [e[0] for e in c.ends] == ["map_edge", "map_edge"]


def test_fold_curve_is_the_existence_limit_of_algorithm1(one_impact):
    c = curve(reference(), one_impact[("fold", -1)])
    for theta in (0.95, 1.05):
        gap, _ = curve_point(c, theta)
        assert abs(gap + algorithm1_existence_gap(reference(theta=theta))) <= 1e-8
    assert all(e[0] in END_REASONS for e in c.ends)


def test_grazing_touch_curve_matches_algorithm1_bisection(one_impact):
    c = curve(reference(), one_impact[("grazing_interior", -1)])
    assert c.kind == "grazing_touch"
    for theta in (0.95, 1.05):
        gap, _ = curve_point(c, theta)
        bisected = algorithm1_grazing_gap(reference(theta=theta), (gap - 0.05, gap + 0.05), xtol=1e-12)
        assert abs(gap - bisected) <= 1e-8


def _settled_k(p: Parameters, t0: float, y0: np.ndarray) -> int:
    return steady_state(p, t0=t0, state=y0, max_periods=20000, settle_tol=1e-9).period_multiple


def test_period_doubling_curve_by_brute_force_bisection(one_impact):
    c = curve(reference(), one_impact[("period_doubling", +1)])
    theta = 1.05
    gap, u = curve_point(c, theta)
    q = reference(theta=theta, gap=gap)
    t, y = Shooting(q, 1, 1).times_states(u)
    # Start every run half a period after the 1/1 cycle's impact (the event solver, not the shooting).
    tm = float(t[0]) + 0.5 * q.T
    ym = Segment(Model(q).free, float(t[0]), y[0]).state(tm)
    lo, hi = gap - 1e-3, gap + 1e-3
    assert _settled_k(q.replace(gap=lo), tm, ym) == 1 and _settled_k(q.replace(gap=hi), tm, ym) == 2
    while hi - lo > 1e-5:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _settled_k(q.replace(gap=mid), tm, ym) == 1 else (lo, mid)
    assert abs(0.5 * (lo + hi) - gap) <= 2e-5, (lo, hi, gap)


def _table() -> dict:
    with open(ROOT / "figures" / "orbit_special_points.csv") as f:
        return {(r["label"], r["kind"], r["leg"]): float(r["gap"]) for r in csv.DictReader(f)}


def test_curves_seeded_off_the_reference_cross_it_at_the_table_points():
    # Seeded from the one-parameter continuation at theta = 0.98, followed to theta = 1.
    table = _table()
    found = special_points(reference(theta=0.98), (-12.5, 11.6))
    checked = 0
    for (kind, direction), sp in found.items():
        leg = "down" if direction < 0 else "up"
        if ("1/1", kind, leg) not in table:
            continue
        c = curve(reference(theta=0.98), sp)
        gap, _ = curve_point(c, 1.0)
        assert abs(gap - table[("1/1", kind, leg)]) <= 1e-6, (kind, gap)
        checked += 1
    assert checked >= 4


def test_neimark_sacker_curve_of_the_three_impact_cycle():
    p = reference(gap=-10.0)
    o = solve_orbit(p, steady_state(p))
    assert (o.period_multiple, o.impacts_per_cycle) == (2, 3)
    b = continue_orbit(o, "gap", (-11.2, -10.0), direction=-1, stop_at_grazing=False)
    sp = next(s for s in b.special if s.kind == "neimark_sacker")
    assert abs(sp.value - _table()[("3/2", "neimark_sacker", "down")]) <= 1e-6
    c = curve(p, sp, k=2, plane=(("gap", "theta"), ((-40.0, 15.0), (0.98, 1.02))), max_points=60)
    assert all(e[0] in END_REASONS for e in c.ends)
    # Off the seed, the cycle solved on its own has a complex pair on the unit circle.
    i = len(c.points) // 3
    assert abs(c.points[i, 1] - 1.0) > 1e-3
    a, th = c.points[i]
    q = reference(gap=a, theta=th)
    t, y = Shooting(q, 2, 3).times_states(c.unknowns[i])
    from impactdamper.analysis.orbits import orbit_from_cycle

    oo = orbit_from_cycle(q, 2, t, y)
    pair = [m for m in oo.multipliers if abs(m.imag) > 1e-6]
    assert pair and abs(abs(pair[0]) - 1.0) <= 1e-6, oo.multipliers


def test_end_reasons_and_bad_input(one_impact):
    assert set(CODIM2_REASONS) < set(END_REASONS)
    sp = one_impact[("fold", -1)]
    with pytest.raises(ValueError, match="`kind`"):
        follow_curve(reference(), 1, sp.point.times, sp.point.states_after, "saddle")
    with pytest.raises(ValueError, match="`bounds`"):
        follow_curve(
            reference(gap=sp.value),
            1,
            sp.point.times,
            sp.point.states_after,
            "fold",
            ("gap", "theta"),
            ((0, 1), (0.9, 1.1)),
        )
    assert math.isfinite(sp.value)
