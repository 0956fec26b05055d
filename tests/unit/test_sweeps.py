"""Tests of the sweeps: analytic thresholds, located transitions, the accelerators
against plain simulation, determinism, and the committed sweep and map data.

Closed forms first; then transitions located by simulation against them; then the sweep
machinery; last, the record: a documented subset of figures/sweep_gap.csv and
figures/map_*.csv recomputed and compared (see ``RECORD_*`` below).
"""

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize

from impactdamper import Parameters, Tolerances
from impactdamper import algorithm1
from impactdamper.core.linear import forced_amplitudes, free_mode, stuck_mode
from impactdamper.core.model import Model
from impactdamper.analysis.continuation import continue_orbit
from impactdamper.analysis.orbits import solve_orbit
from impactdamper.analysis.ladder import carry_state, solve_point
from impactdamper.analysis.point import SweepSettings, label_of
from impactdamper.analysis.batch import random_starts_batch
from impactdamper.analysis.sweeps import locate_transition, sweep, with_value
from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.analysis.transitions import (
    algorithm1_grazing_gap,
    no_contact_gap,
    rigid_amplitude,
    stuck_liftoff_gap,
)

ROOT = Path(__file__).resolve().parents[2]
REF = Parameters()
CASES = [Parameters(), Parameters(theta=0.8), Parameters(theta=1.3, delta1=0.1, delta2=0.02), Parameters(N=0.9, mu=0.2)]
# Every point simulated: what the accelerators must agree with.
SIMULATION = SweepSettings(continuation=False)


# --- closed forms -----------------------------------------------------------------------------
@pytest.mark.parametrize("p", CASES)
def test_liftoff_threshold_is_where_the_contact_force_of_the_joined_motion_reaches_zero(p):
    # Independent: the model's own contact-force functional on the stuck mode's forced
    # response, sampled over a period; at the threshold its least value is zero.
    def least(g):
        q = p.replace(gap=g)
        model = Model(q)
        ts = np.linspace(0.0, q.T, 4001)
        F = model.contact_force.of_state(ts, model.stuck.forced(ts))
        return float(np.min(F)) / model.force_scale

    g = stuck_liftoff_gap(p)
    root = scipy.optimize.brentq(least, g - 1.0, g + 1.0, xtol=1e-13)
    # Sampling 4001 points per period misses the minimum by at most ~|G| (pi/4000)^2 / 2.
    assert abs(root - g) < 1e-5 * abs(g)
    assert least(g - 1e-3) > 0.0 > least(g + 1e-3)


@pytest.mark.parametrize("p", CASES)
def test_no_contact_threshold_is_the_largest_forced_relative_displacement(p):
    mode = free_mode(p)
    ts = np.linspace(0.0, p.T, 20001)
    y = mode.forced(ts)
    largest = float(np.max(y[:, 1] - y[:, 0])) / p.x_st
    assert no_contact_gap(p) == pytest.approx(largest, rel=1e-7)


@pytest.mark.parametrize("p", CASES)
def test_reference_amplitudes(p):
    # Rigidly attached: the stuck mode's forced amplitude; alone: the suppressor's mass -> 0.
    assert rigid_amplitude(p) == pytest.approx(abs(stuck_mode(p).Yhat[0]) / p.x_st, rel=1e-12)
    tiny = p.replace(mu=1e-10)
    assert LinearDevice.bare(p.delta1).amplitude([p.theta])[0] == pytest.approx(
        abs(forced_amplitudes(tiny)[0]) / p.x_st, rel=1e-8
    )


def test_reference_case_thresholds():
    # The reference case (theta = 1): -(1/0.5)^2/|-0.08 + 0.1 i| and U1 of eq. (12).
    assert stuck_liftoff_gap(REF) == pytest.approx(-4.0 / abs(-0.08 + 0.1j), rel=1e-14)
    assert no_contact_gap(REF) == pytest.approx(algorithm1(REF).U1 / REF.x_st, rel=1e-14)


def test_algorithm1_grazing_three_ways():
    g = algorithm1_grazing_gap(REF, (-5.8, -10.0), xtol=1e-12)
    # The interior gap minimum of the orbit crosses zero there (a root, found by brentq) ...
    root = scipy.optimize.brentq(lambda x: algorithm1(REF.replace(gap=x)).min_gap, g + 0.05, g - 0.05, xtol=1e-13)
    assert abs(root - g) < 1e-9
    # ... and the orbit's continuation (saltation-matrix shooting) meets its grazing there.
    with np.errstate(over="ignore", invalid="ignore"):
        branch = continue_orbit(solve_orbit(REF, "alg1"), "gap", (-10.0, -5.8), direction=-1)
    graze = [s.value for s in branch.special if s.kind == "grazing_interior"]
    assert graze and abs(graze[0] - g) < 1e-8
    assert -9.0 < g < -8.7


def test_labels():
    assert [
        label_of(*a)
        for a in (
            ("stuck", 1, 0),
            ("no_contact", 1, 0),
            ("single_impact", 1, 1),
            ("multi_impact", 2, 3),
            ("chatter", 3, 33),
            ("nonperiodic", 0, 12),
        )
    ] == ["stuck", "0/1", "1/1", "3/2", "c/3", "np"]


# --- transitions located by simulation --------------------------------------------------------
@pytest.mark.slow
def test_liftoff_located_by_simulation_matches_the_analytic_threshold():
    g = stuck_liftoff_gap(REF)
    a = solve_point(REF.replace(gap=g - 0.01), settings=SIMULATION)
    b = solve_point(REF.replace(gap=g + 0.01), previous=a, settings=SIMULATION)
    assert (a.label, b.label) == ("stuck", "c/1")
    tr = locate_transition(REF, "gap", a, b, "up", settings=SIMULATION, xtol=2e-4)
    # (The event solver resolves lift-offs to ~1e-6 x_st of the threshold; closer, the contact
    # force touches zero almost tangentially and the bisection stops, `stopped`.)
    assert tr.lower - 1e-6 <= g <= tr.upper + 1e-6
    assert tr.upper - tr.lower <= 2e-4


@pytest.mark.slow
def test_first_contact_located_by_simulation_matches_U1():
    u1 = no_contact_gap(REF)
    a = solve_point(REF.replace(gap=u1 + 0.05), settings=SIMULATION)
    b = solve_point(REF.replace(gap=u1 - 0.05), previous=a, settings=SIMULATION)
    assert a.label == "0/1" and b.label != "0/1"
    tr = locate_transition(REF, "gap", a, b, "down", settings=SIMULATION, xtol=1e-7)
    assert tr.before == "0/1" and not tr.stopped
    assert tr.lower - 1e-9 <= u1 <= tr.upper + 1e-9


def test_one_impact_motion_ends_where_algorithm1_grazes():
    # Downward from the stated case the settled one-impact motion is Algorithm No. 1's orbit,
    # until that orbit touches the stop between impacts.
    g = algorithm1_grazing_gap(REF, (-5.8, -10.0), xtol=1e-12)
    # From -8 (where the step-1 start settles on 1/1; nearer g a 4/3 motion coexists).
    a = sweep(REF, "gap", [-8.0, -8.4, g + 0.02])[-1]
    b = solve_point(REF.replace(gap=g - 0.02), previous=a)
    assert a.label == "1/1" and b.label != "1/1"
    tr = locate_transition(REF, "gap", a, b, "down", xtol=1e-7)
    assert tr.lower - 1e-9 <= g <= tr.upper + 1e-9


# --- the accelerators agree with plain simulation ---------------------------------------------
@pytest.mark.parametrize(
    "gaps,method",
    [
        ((-5.75, -5.8), "continuation"),
        ((-25.05, -25.0), "newton"),
        ((-33.0, -32.9), "closed_form"),
        ((12.5, 12.4), "closed_form"),
    ],
)
def test_accelerated_point_equals_simulated_point(gaps, method):
    prev = solve_point(REF.replace(gap=gaps[0]))
    fast = solve_point(REF.replace(gap=gaps[1]), previous=prev)
    slow = solve_point(REF.replace(gap=gaps[1]), previous=prev, settings=SIMULATION)
    assert fast.method == method and slow.method == "simulation"
    assert fast.label == slow.label
    assert fast.x1_max == pytest.approx(slow.x1_max, rel=1e-7)
    # Both settle to settle_tol = 1e-9; the last, smallest bounces of a chatter sequence amplify it.
    assert np.allclose(fast.velocities, slow.velocities, rtol=1e-6, atol=1e-6)
    if method != "closed_form":
        assert fast.stable and 0.0 < fast.multiplier < 1.0


def test_carry_projects_onto_the_stop():
    p = REF.replace(gap=-6.0)
    state = np.array([1.0, 1.0 - 5.9, 2.0, 3.0])  # gap +0.1 at -5.8, -0.1 at -6.0
    full, how = carry_state(p, state, "free")
    assert how == "projected" and full[1] - full[0] == pytest.approx(p.Delta0)
    assert np.array_equal(full[[0, 2, 3]], state[[0, 2, 3]])
    full, how = carry_state(REF.replace(gap=-5.0), state, "free")
    assert how == "neighbour" and np.array_equal(full, state)


# --- determinism and inputs -----------------------------------------------------------------
def test_small_sweep_is_deterministic():
    values = np.linspace(-7.0, -5.0, 5)
    one = [p.row() for p in sweep(REF, "gap", values)]
    two = [p.row() for p in sweep(REF, "gap", values)]
    assert one == two
    assert [r["label"] for r in one] == ["1/1"] * 5


def test_random_starts_do_not_depend_on_chunking():
    values = [12.5, 13.0]
    together = random_starts_batch(REF, "gap", values, 2, seed=7, indices=[3, 4])
    apart = random_starts_batch(REF, "gap", values[:1], 2, seed=7, indices=[3]) + random_starts_batch(
        REF, "gap", values[1:], 2, seed=7, indices=[4]
    )
    assert [[p.row() for p in r] for r in together] == [[p.row() for p in r] for r in apart]
    for row in together:
        for p in row:
            assert Model(p.p).gap_of(p.start_state) >= 0.0


def test_delta_sets_both_dampings():
    p = with_value(REF, "delta", 0.1)
    assert (p.delta1, p.delta2) == (0.1, 0.1)


@pytest.mark.parametrize(
    "kwargs,name",
    [
        ({"max_periods": 10}, "max_periods"),
        ({"settle_tol": 2.0}, "settle_tol"),
        ({"max_periods_after_nonperiodic": 500}, "max_periods_after_nonperiodic"),
    ],
)
def test_bad_settings_name_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        SweepSettings(**kwargs)


def test_bad_parameter_name():
    with pytest.raises(ValueError, match="`parameter`"):
        sweep(REF, "Delta", [1.0])


# --- the record: committed data recomputed on a documented subset ---------------------------
# Sweep: in each direction, every RECORD_SWEEP_EVERY-th row with a periodic label is
# recomputed by plain simulation from the state it started from (stored in the row), so the
# check also tests the accelerators against simulation. (The regime maps' rows are swept again
# cell by cell in tests/workflow/test_figures_record.py.)
RECORD_SWEEP_EVERY = 100


def _settings(section: dict, solver: dict, **changes) -> SweepSettings:
    return SweepSettings(
        settle_tol=float(section["settle_tol"]),
        max_periods=int(section["max_periods"]),
        max_periods_after_nonperiodic=int(section["max_periods_after_nonperiodic"]),
        max_period_multiple=int(section["max_period_multiple"]),
        tolerances=Tolerances(gap_tol=float(solver["gap_tol"]), chatter_tol=float(solver["chatter_tol"])),
        **changes,
    )


def _read(path: Path):
    import csv

    assert path.exists(), f"{path} is missing: run the workflow (snakemake --cores 2) to regenerate the record"
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.slow
def test_committed_sweep_reproduces_on_a_subset():
    cfg = json.loads((ROOT / "figures" / "sweep_gap_settings.json").read_text())
    base = Parameters(**{k: float(cfg["reference"][k]) for k in Parameters.names()})
    settings = _settings(cfg["sweep"], cfg["solver"])
    rows = _read(ROOT / "figures" / "sweep_gap.csv")
    checked = 0
    for r in rows:
        if int(r["index"]) % RECORD_SWEEP_EVERY or r["label"] in ("np", "err") or r["start"] == "default":
            continue
        p = with_value(base, cfg["parameter"], float(r["value"]))
        state = np.array([float(r[c]) for c in ("x1_0", "x2_0", "v1_0", "v2_0")])
        # Stored to 12 digits: a state on the stop may come back ~1e-11 x_st inside it.
        state, _ = carry_state(p, state, "free")
        pt = solve_point(
            p, float(r["value"]), state=state, settings=replace(settings, max_periods=4 * settings.max_periods)
        )
        assert pt.label == r["label"], f"{r['direction']} row {r['index']} ({r['value']})"
        assert pt.x1_max == pytest.approx(float(r["x1_max"]), rel=1e-6)
        checked += 1
    assert checked >= 4
