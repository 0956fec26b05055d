"""The paper's claims, the aligned cross-check of settled cycles and the interval search
(impactdamper.studies.replication.claims, impactdamper.studies.intervals and the claims stage's
impactdamper.studies.claims).

Regression guarded: the headline cross-check compared the exact solver's settled cycle
(described on a fresh run, clock rebased) with the solve_ivp impacts in the same absolute time
window of a run still in its transient, found 0.98 T of difference and still printed "agrees"
(counts and claims were compared, not times). Here the comparison is fed perturbed cycles and
must fail; fed the real located case it must agree to far below its tolerance.
"""

from __future__ import annotations

import math
import numpy as np

import pytest

import impactdamper as idp
from impactdamper.studies.intervals import Interval, _claim_intervals, distance_to, intersect, true_intervals
from impactdamper.studies.claims.search import check_rows, reference_check, search_parameter
from impactdamper.studies.replication.claims import compare_cycles

TOL = 1e-8


@pytest.fixture(scope="module")
def located():
    """The located case's settled cycle (T_c = 2T, three impacts) from the paper's step 1."""
    s = idp.steady_state(idp.Parameters(gap=-9.6), backend="python")
    assert (s.period_multiple, s.impacts_per_cycle) == (2, 3)
    return s


def cycle(s, shift_periods=0):
    return [(i.t + shift_periods * s.p.T, i.velocity) for i in s.impacts]


def compare(s, other, k_other=None):
    p = s.p
    return compare_cycles(
        s.impacts,
        s.period_multiple,
        other,
        s.period_multiple if k_other is None else k_other,
        p.T,
        p.x_st * p.omega,
        TOL,
        TOL,
    )


# --- closed-form cases first ---------------------------------------------------------------
@pytest.mark.parametrize("shift", [0, 1, 2, 7, -3])
def test_same_cycle_on_another_clock_agrees_exactly(located, shift):
    # The clocks of two runs differ by whole periods: the alignment must absorb any of them.
    c = compare(located, cycle(located, shift))
    assert c.agree and c.matched == 3 and c.reason == ""
    assert c.max_time_difference_over_T < 1e-12 and c.max_velocity_difference_rel == 0.0
    assert c.shift_periods == (-shift) % 2 or c.max_time_difference_over_T < 1e-12


@pytest.mark.parametrize("dt_over_T", [1e-6, 1e-3, 0.3])
def test_a_shifted_impact_fails(located, dt_over_T):
    other = cycle(located)
    t, v = other[1]
    other[1] = (t + dt_over_T * located.p.T, v)
    c = compare(located, other)
    assert not c.agree
    assert c.max_time_difference_over_T == pytest.approx(dt_over_T, rel=1e-6)
    assert "time difference" in c.reason


def test_a_whole_cycle_shifted_by_half_a_period_fails(located):
    # A cycle on the wrong forcing phase (a period-T shift is a symmetry; T/2 is not).
    c = compare(located, cycle(located, 0.5))
    # Paired with the nearest impacts of the shifted cycle, some still lie far apart.
    assert not c.agree and c.max_time_difference_over_T > 0.1


def test_a_missing_impact_fails(located):
    for drop in range(3):
        other = [imp for i, imp in enumerate(cycle(located)) if i != drop]
        c = compare(located, other)
        assert not c.agree and math.isinf(c.max_time_difference_over_T)
        assert "different impact counts: 3 and 2" in c.reason


def test_an_extra_impact_fails(located):
    other = cycle(located) + [(located.impacts[0].t + 0.5 * located.p.T, 1.0)]
    c = compare(located, other)
    assert not c.agree and "different impact counts: 3 and 4" in c.reason


def test_a_changed_velocity_fails(located):
    other = cycle(located)
    t, v = other[2]
    other[2] = (t, v + 1e-6 * located.p.x_st * located.p.omega)
    c = compare(located, other)
    assert not c.agree and c.max_velocity_difference_rel == pytest.approx(1e-6, rel=1e-6)
    assert "velocity difference" in c.reason


def test_a_different_period_multiple_fails(located):
    c = compare(located, cycle(located), k_other=1)
    assert not c.agree and "different period multiples" in c.reason
    c = compare(located, cycle(located), k_other=0)
    assert not c.agree and "did not settle" in c.reason


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_tolerances_are_checked(located, bad):
    with pytest.raises(ValueError, match="time_tol"):
        compare_cycles(located.impacts, 2, cycle(located), 2, located.p.T, 10.0, bad, TOL)


# --- the real cross-check -------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("gap", [-5.8, -9.6])
def test_exact_and_solve_ivp_settled_cycles_agree_when_aligned(gap):
    """The exact solver against the independent solve_ivp integrator (DOP853, 1e-10), both
    from the paper's step 1: the settled cycles agree far below the tolerance."""
    from impactdamper.baselines.ivp import simulate_ivp

    p = idp.Parameters(gap=gap)
    s = idp.steady_state(p, backend="python")
    k = s.period_multiple
    n = s.periods + 8
    traj = simulate_ivp(p, (n + 1) * p.T, method="DOP853", rtol=1e-10, atol=1e-10)
    ivp_cycle = traj.impacts((n - k) * p.T, n * p.T)
    c = compare_cycles(s.impacts, k, ivp_cycle, k, p.T, p.x_st * p.omega, TOL, TOL)
    assert c.agree, c.reason
    assert c.max_time_difference_over_T < 1e-9
    # The absolute-window comparison that this replaces: the same number of impacts in the
    # same absolute window, yet nowhere near each other (the run is still in its transient).
    same_window = traj.impacts(s.cycle_start - 1e-6 * p.T, s.cycle_start + s.cycle_duration)
    if len(same_window) == len(s.impacts):
        naive = max(abs(a.t - b.t) / p.T for a, b in zip(same_window, s.impacts))
        assert naive > 100 * c.max_time_difference_over_T


# --- the interval search --------------------------------------------------------------------
def test_true_intervals_bisects_ends_to_the_relative_tolerance():
    lo, hi = 0.3141592, 0.7182818
    pred = lambda x: lo <= x <= hi  # noqa: E731
    xs = [i / 20 for i in range(21)]
    (iv,) = true_intervals(xs, [pred(x) for x in xs], pred, 1e-4, 0.01)
    assert abs(iv.lo - lo) <= 1e-4 * lo and abs(iv.hi - hi) <= 1e-4 * hi
    assert pred(iv.lo_bracket[0]) and not pred(iv.lo_bracket[1])
    assert not (iv.lo_open or iv.hi_open)


def test_runs_at_the_window_edge_are_open_and_gaps_split_runs():
    pred = lambda x: x < 0.2 or 0.5 < x < 0.6  # noqa: E731
    xs = [i / 100 for i in range(101)]
    ivs = true_intervals(xs, [pred(x) for x in xs], pred, 1e-4, 0.01)
    assert len(ivs) == 2
    assert ivs[0].lo_open and ivs[0].lo == 0.0 and ivs[0].hi == pytest.approx(0.2, abs=1e-4 * 0.2)
    assert ivs[1].lo == pytest.approx(0.5, abs=1e-4) and ivs[1].hi == pytest.approx(0.6, abs=1e-4)


def test_both_is_the_intersection_and_distance_is_to_the_nearest_point():
    xs = [i / 10 for i in range(11)]
    r = _claim_intervals(xs, lambda x: 0.2 <= x <= 0.6, lambda x: 0.4 <= x <= 0.9, 1e-6, 0.01)
    (both,) = r["both"]
    assert both.lo == pytest.approx(0.4, abs=1e-6) and both.hi == pytest.approx(0.6, abs=1e-6)
    assert distance_to(r["both"], 0.5) == (0.0, 0.5)
    d, x = distance_to(r["both"], 0.8)
    assert d == pytest.approx(0.2, abs=1e-6) and x == pytest.approx(0.6, abs=1e-6)
    assert distance_to([], 0.5) == (math.inf, None)
    assert intersect([Interval(0, 1, False, False, None, None)], [Interval(2, 3, False, False, None, None)]) == []


@pytest.mark.slow
def test_search_along_the_gap_finds_the_known_range():
    """Along Delta0/x_st alone the claims' common range contains the located case -9.6 and not
    the stated -5.8 (the gap scan's finding, by the same predicates on another grid)."""
    p = idp.Parameters()
    r = search_parameter(
        p,
        "gap",
        [-10.0, -9.8, -9.6, -9.4, -9.2],
        [-10.0 + 0.05 * i for i in range(17)],
        gap_tol=1e-12,
        steady_kwargs={},
        rel_tol=1e-3,
        floor=1.0,
    )
    both = r["intervals"]["both"]
    assert any(iv.lo < -9.6 < iv.hi for iv in both)
    assert not any(iv.lo <= -5.8 <= iv.hi for iv in both)
    with pytest.raises(ValueError, match="`name`"):
        search_parameter(p, "nope", [0.0], [0.0], gap_tol=1e-12, steady_kwargs={}, rel_tol=1e-3, floor=1.0)


def test_reference_check_agrees_and_can_fail():
    """The compiled claim (b) at two theta values, repeated by the pure-Python solver: the rows
    as computed agree; a row whose period multiple is changed is reported as a mismatch."""
    p = idp.Parameters()
    kw = {"max_periods": 400}
    r = search_parameter(p, "theta", [0.9, 1.0], [0.9, 1.0], gap_tol=1e-12, steady_kwargs=kw, rel_tol=1e-2, floor=1.0)
    rows = r["grid_b"]
    check = reference_check(p, "theta", rows, kw)
    assert (check["points"], check["agree"], check["mismatches"]) == (2, 2, [])
    wrong = [dict(rows[0], period_multiple=rows[0]["period_multiple"] + 1), rows[1]]
    check = reference_check(p, "theta", wrong, kw)
    assert (check["points"], check["agree"], check["settling"], check["cycles"]) == (2, 1, 0, 1)
    assert check["mismatches"][0]["value"] == 0.9


def test_check_rows_takes_every_nth_value_and_the_final_brackets():
    r = {
        "grid_b": [{"value": float(v)} for v in range(10)],
        "bisection_points": [{"value": 2.5}, {"value": 2.75}, {"value": 7.5}],
        "intervals": {"b": [Interval(2.75, 9.0, False, True, (2.75, 2.5), None)]},
    }
    assert [row["value"] for row in check_rows(r, 4)] == [0.0, 2.5, 2.75, 4.0, 8.0]


def test_nearest_both_measures_from_the_stated_value():
    """A gathered search record: both claims hold on [0.9, 0.95] and [1.2, 1.3]; stated 1.0 is
    0.05 from the first (5 % of |stated|)."""
    from impactdamper.studies.claims.search import nearest_both

    both = [
        {"lo": 0.9, "hi": 0.95, "lo_open": False, "hi_open": False},
        {"lo": 1.2, "hi": 1.3, "lo_open": False, "hi_open": True},
    ]
    got = nearest_both({"stated": 1.0, "intervals": {"both": both}})
    assert got["nearest"] == 0.95 and got["intervals"] == 2
    assert got["distance"] == pytest.approx(0.05, abs=1e-15)
    assert got["relative_distance"] == pytest.approx(0.05, abs=1e-15)
    nowhere = nearest_both({"stated": 0.0, "intervals": {"both": []}})
    assert nowhere["nearest"] is None and nowhere["distance"] is None and nowhere["relative_distance"] is None


# --- adaptive refinement of claim (b)'s grid --------------------------------------------------
def test_refine_grid_finds_a_window_between_other_labels_down_to_the_floor():
    """A label "B" on [0.4985, 0.5) (narrower than the step 0.01) between "A" and "C": the
    refinement splits every pair with different labels and finds it; a window of "B" inside a
    run of "A" narrower than the step is not seen (nothing there asks for refinement)."""

    def label(x):
        if 0.4985 <= x < 0.5 or 0.2031 <= x <= 0.2049:
            return "B"
        return "A" if x < 0.5 else "C"

    calls = []

    def rows_at(xs):
        calls.append(len(xs))
        return [{"value": x, "label": label(x)} for x in xs]

    from impactdamper.studies.claims.search import refine_grid

    rows, rounds = refine_grid([i / 100 for i in range(101)], rows_at, 0.01 / 2**4)
    b = [r["value"] for r in rows if r["label"] == "B"]
    assert b and all(0.4985 <= x < 0.5 for x in b)  # the window between A and C, not the one inside A
    assert rounds == len(calls) - 1 and max(r["level"] for r in rows) == rounds
    xs = [r["value"] for r in rows]
    assert xs == sorted(xs) and len(set(xs)) == len(xs)
    # Every pair of neighbours with different labels is the floor apart (within rounding).
    assert all(
        b_["value"] - a["value"] < 1.01 * 0.01 / 2**4 for a, b_ in zip(rows, rows[1:]) if a["label"] != b_["label"]
    )
    with pytest.raises(ValueError, match="`min_step`"):
        refine_grid([0.0, 1.0], rows_at, 0.0)


def test_refinement_finds_every_claim_b_window_of_a_brute_force_fine_grid():
    """theta from 0.86 to 0.94 (stated point otherwise), Algorithm No. 2 from the paper's step 1
    on the compiled batch: the refined search (step 0.01, floor 0.01/8) against a brute-force
    grid at the floor (65 values). Every run of values where claim (b) holds on the fine grid
    must contain a refined point where it holds, the two grids must give the same motion where
    they share a value, and every end of a run must lie within one fine step of a change of the
    refined grid."""
    from impactdamper.analysis.point import SweepSettings
    from impactdamper.studies.claims.search import _batch_rows, refine_grid
    from impactdamper.studies.intervals import true_runs

    p = idp.Parameters()
    st = SweepSettings(
        settle_tol=1e-10,
        max_periods=4000,
        max_periods_after_nonperiodic=4000,
        max_period_multiple=8,
        continuation=False,
        rescue=True,
    )
    step, levels = 0.01, 3
    floor = step / 2**levels
    coarse = [round(0.86 + step * i, 12) for i in range(9)]
    rows, _ = refine_grid(coarse, lambda xs: _batch_rows(p, "theta", xs, st), floor)
    fine = _batch_rows(p, "theta", [round(0.86 + floor * i, 12) for i in range(8 * 8 + 1)], st)
    runs = true_runs([r["claim_b"] for r in fine])
    assert runs, "claim (b) holds somewhere on theta 0.86-0.94 (both claims hold near 0.90)"
    refined = {round(r["value"], 12): r for r in rows}
    for i, j in runs:
        lo, hi = fine[i]["value"], fine[j]["value"]
        assert any(r["claim_b"] and lo - 1e-12 <= r["value"] <= hi + 1e-12 for r in rows), (lo, hi)
    for r in fine:
        twin = refined.get(round(r["value"], 12))
        if twin is not None:
            assert (twin["label"], twin["claim_b"]) == (r["label"], r["claim_b"]), r["value"]
    changes = [0.5 * (a["value"] + b["value"]) for a, b in zip(rows, rows[1:]) if a["claim_b"] != b["claim_b"]]
    for i, j in runs:
        for end in (fine[i]["value"], fine[j]["value"]):
            if 0 < i and j < len(fine) - 1:
                assert min(abs(c - end) for c in changes) <= floor + 1e-12, end


def test_end_checks_are_counted_by_what_they_rest_on():
    """Two compared within tolerance, one with nothing to compare per claim, one compared
    outside tolerance, one with different verdicts: the counts say so (not "6 of 6 agree")."""
    from impactdamper.studies.replication.gapscan import count_end_checks

    a_ok = {
        "claim": "a",
        "exact": True,
        "independent": True,
        "comparison": {"periodicity_residual": 1e-10, "agree": True},
    }
    a_none = {
        "claim": "a",
        "exact": False,
        "independent": False,
        "comparison": {"periodicity_residual": None, "agree": True},
    }
    b_ok = {
        "claim": "b",
        "exact": True,
        "independent": True,
        "exact_period_multiple": 2,
        "independent_period_multiple": 2,
        "details": {"agree": True},
    }
    b_none = dict(
        b_ok, exact=False, independent=False, exact_period_multiple=0, independent_period_multiple=0, details={}
    )
    b_off = dict(
        b_ok,
        exact=False,
        independent=False,
        exact_period_multiple=4,
        independent_period_multiple=4,
        details={"agree": False},
    )
    b_diff = dict(b_ok, independent=False, independent_period_multiple=1, details={"agree": False})
    got = count_end_checks([a_ok, a_none, b_ok, b_none, b_off, b_diff])
    assert got == {
        "checks": 6,
        "compared_within": 2,
        "nothing_to_compare": 2,
        "outside_tolerance": 2,
        "different_verdict": 1,
    }


def _boundary_edges(label: dict, n: int, step: int = 1) -> set:
    """Pairs of neighbouring lattice points ``step`` apart (of an n x n lattice) whose labels
    differ or do not settle."""
    out = set()
    for i in range(0, n, step):
        for j in range(0, n, step):
            for k in ((i + step, j), (i, j + step)):
                if k in label and (label[(i, j)] != label[k] or "np" in (label[(i, j)], label[k])):
                    out.add(((i, j), k))
    return out


def test_map_refinement_resolves_every_boundary_of_a_brute_force_fine_grid():
    """theta 0.935-0.975 against N 0.47-0.55 (the others as stated), where both claims, (b)
    only and neither meet on the (theta, N) map: a 5 x 5 grid (steps 0.01 x 0.02) refined twice
    (floor 0.0025 x 0.005, the full map's steps) against a brute-force 17 x 17 grid at the
    floor. Every pair of fine-grid neighbours whose labels differ (or that does not settle) must
    have both points evaluated by the refinement, with the same label, in fewer points than the
    brute force; one halving alone (floor 0.005 x 0.01) misses some of them."""
    from impactdamper.analysis.point import SweepSettings
    from impactdamper.studies.claims.maps import claims_cells
    from impactdamper.studies.claims.maps import _map_label, refine_claims_map

    p = idp.Parameters()
    st = SweepSettings(
        settle_tol=1e-9, max_periods=1000, max_periods_after_nonperiodic=1000, max_period_multiple=8, rescue=False
    )
    n, (x0, x1), (y0, y1) = 17, (0.935, 0.975), (0.47, 0.55)
    fx, fy = (x1 - x0) / (n - 1), (y1 - y0) / (n - 1)

    def points(ks):
        return [(round(x0 + i * fx, 12), round(y0 + j * fy, 12)) for i, j in ks]

    def labels(ks):
        return dict(
            zip(ks, (_map_label(r) for r in claims_cells(p, "theta", "N", points(ks), gap_tol=1e-9, settings=st)))
        )

    fine = labels([(i, j) for j in range(n) for i in range(n)])
    edges = _boundary_edges(fine, n)
    assert {"both", "b", "neither"} <= set(fine.values()), "the box holds both claims, (b) only and neither"
    base_keys = [(i, j) for j in range(0, n, 4) for i in range(0, n, 4)]
    base = claims_cells(p, "theta", "N", points(base_keys), gap_tol=1e-9, settings=st)

    def refined(levels):
        added, stats = refine_claims_map(
            p, "theta", (x0, x1, 5), "N", (y0, y1, 5), levels=levels, gap_tol=1e-9, settings=st, base=base
        )
        assert stats["refined_points"] == len(added) == sum(stats["points_per_level"])
        assert {r["level"] for r in added} <= set(range(1, levels + 1))
        seen = dict(zip(base_keys, (_map_label(r) for r in base)))
        for r in added:
            k = (round((r["x"] - x0) / fx), round((r["y"] - y0) / fy))
            assert k not in seen  # each point evaluated once
            seen[k] = _map_label(r)
        return seen, stats

    seen, stats = refined(2)
    assert stats["x_floor"] == pytest.approx(fx, rel=1e-9) and stats["y_floor"] == pytest.approx(fy, rel=1e-9)
    missing = [e for e in edges if e[0] not in seen or e[1] not in seen]
    assert not missing, missing
    assert all(seen[k] == fine[k] for k in seen)  # the same motion at the same values
    assert len(seen) < 0.8 * n * n
    # One halving: every boundary between points 2 fine steps apart is seen, not those at the floor.
    seen1, _ = refined(1)
    assert not [e for e in _boundary_edges(fine, n, 2) if e[0] not in seen1 or e[1] not in seen1]
    assert [e for e in edges if e[0] not in seen1 or e[1] not in seen1]
    with pytest.raises(ValueError, match="`levels`"):
        refine_claims_map(p, "theta", (x0, x1, 5), "N", (y0, y1, 5), levels=7, gap_tol=1e-9, settings=st, base=base)
    with pytest.raises(ValueError, match="`base`"):
        refine_claims_map(
            p, "theta", (x0, x1, 5), "N", (y0, y1, 5), levels=1, gap_tol=1e-9, settings=st, base=base[:-1]
        )


@pytest.mark.slow
def test_adaptive_claims_grid_is_the_brute_force_where_computed_and_its_check_counts_the_rest():
    """theta 0.9-1.1 against N 0.45-0.65 (a 21 x 11 piece of the theta_N map's box): the grid
    computed from every 4th point down, against every cell computed. Computed cells are the
    brute force's (every cell is independent); every filled cell's block had agreeing corners;
    the check rows count exactly the filled cells that differ there; fewer cells computed."""
    from impactdamper.analysis.point import SweepSettings
    from impactdamper.studies.claims.maps import CELL_KEY, adaptive_claims_map, claims_map

    p = idp.Parameters()
    st = SweepSettings(
        settle_tol=1e-9, max_periods=1000, max_periods_after_nonperiodic=1000, max_period_multiple=8, rescue=False
    )
    xa, ya = (0.9, 1.1, 21), (0.45, 0.65, 11)
    brute = claims_map(p, "theta", np.linspace(*xa), "N", np.linspace(*ya), gap_tol=1e-9, settings=st)
    rows, stats = adaptive_claims_map(
        p, "theta", xa, "N", ya, coarse_step=4, check_every=2, gap_tol=1e-9, settings=st, workers=2
    )
    assert [(r["x"], r["y"]) for r in rows] == [(r["x"], r["y"]) for r in brute]
    computed = [r["periods"] is not None for r in rows]
    assert sum(computed) == stats["computed"] < len(rows) and stats["filled"] == len(rows) - stats["computed"]
    assert all(a == b for a, b, c in zip(rows, brute, computed) if c)
    key = lambda r: tuple(str(r[k]) for k in CELL_KEY)  # noqa: E731
    wrong = {(r["x"], r["y"]) for r, b in zip(rows, brute) if key(r) != key(b)}
    on_check_rows = {(r["x"], r["y"]) for j, r in enumerate(rows) if (j // 21) % 2 == 0} & wrong
    assert stats["check"]["differences"] == len(on_check_rows)
    assert stats["check"]["cells"] == 6 * 21 and len(wrong) <= 0.02 * len(rows), sorted(wrong)
