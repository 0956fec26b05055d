"""The Lyapunov spectrum on the compiled path (core/compiled/tangent.py behind the front door's
``lyapunov_spectrum(..., backend="compiled")``), the many-point call's labels and the command.

The compiled walk is held to the reference walk (core/tangent.py: the same motion, the same
exponents to rounding where the motion is regular, the same events until rounding grows where
it is chaotic) and, like the reference in test_lyapunov.py, to consistency checks that do not use
either walk's saltation matrices (tests/lyapunov_checks.py; they share its flow or its event
solver): Floquet multipliers of the orbit solver, the sum rule's closed form, Benettin's
two-trajectory estimate with the solver alone. The independent check (no library code) is
test_benettin_ivp.py's.
"""

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.analysis.lyapunov import LABELS, SIGNIFICANCE, ZERO_BAND
from impactdamper.analysis.point import SweepSettings
from impactdamper.cli import main
from impactdamper.cli.parser import LYAPUNOV_KEYS
from impactdamper.core.backends import get_backend
from impactdamper.core.compiled.layout import ERR_WALK, MARCH_ROOT
from impactdamper.core.simulate import Tolerances
from lyapunov_checks import (
    BENETTIN_FLOOR,
    FLOQUET_TOL,
    SAME_MOTION_TOL,
    SUM_RULE_TOL,
    benettin,
    block_estimate,
    check_sum_rule,
    floquet_exponents,
)

REF = idp.Parameters()
ROOT = Path(__file__).resolve().parents[2]
# The compiled walk against the reference's, where the motion is regular: both carry the same
# frame by the same matrices (modal transition matrices, the same saltation formulas), the
# compiled one with Gram-Schmidt where the reference uses Householder, so they differ by
# rounding (measured: 8e-15 per period at the stated case, 5e-13 at a chatter cycle); 1e-9.
BACKENDS_TOL = 1e-9
# The share of time in contact sums the flights between the two loops' events, whose times
# agree to ~1e-10 T each (tests/unit/test_compiled.py): over a chatter cycle's ~90 events a
# period, 1.2e-9 measured (gap -28, R = 0.9); 1e-8.
CONTACT_TOL = 1e-8


def compiled(p, **run):
    return idp.lyapunov_spectrum(p, backend="compiled", **run)


def reference(p, **run):
    return idp.lyapunov_spectrum(p, backend="python", **run)


def assert_same_spectrum(c, r):
    """The same exponents (to BACKENDS_TOL), increments and sections, events and dimension."""
    assert (c.backend, r.backend, c.fallback) == ("compiled", "python", "")
    assert (c.impacts, c.captures, c.liftoffs, c.dimension) == (r.impacts, r.captures, r.liftoffs, r.dimension)
    finite = np.isfinite(r.exponents)
    assert np.array_equal(finite, np.isfinite(c.exponents))
    assert np.max(np.abs(c.exponents[finite] - r.exponents[finite])) <= BACKENDS_TOL
    assert np.max(np.abs(c.increments[:, finite] - r.increments[:, finite])) <= BACKENDS_TOL
    assert np.max(np.abs(c.sections - r.sections) / np.array([1.0, 1.0, REF.omega, REF.omega])) <= BACKENDS_TOL
    assert abs(c.contact_time - r.contact_time) <= CONTACT_TOL


def test_compiled_walk_is_the_reference_walk_at_the_stated_case():
    run = dict(periods=200, transient=100, warmup=50)
    assert_same_spectrum(compiled(REF, **run), reference(REF, **run))


def test_compiled_walk_grows_its_buffers_through_a_long_chatter_sequence():
    """R = 0.9 pressed together: ~90 events a period, more than the walk's first buffers hold
    (64), so a period is run again with larger ones; the same spectrum as the reference's."""
    p = REF.replace(gap=-28.0, R=0.9)
    run = dict(periods=20, transient=20, warmup=10, blocks=2)
    c, r = compiled(p, **run), reference(p, **run)
    assert c.impacts / c.periods > 64
    assert_same_spectrum(c, r)


def test_stated_case_compiled_matches_floquet_multipliers():
    s = compiled(REF, periods=1000, transient=300, warmup=100)
    fl = floquet_exponents(REF)
    assert np.max(np.abs(s.exponents - fl)) <= FLOQUET_TOL, (s.exponents, fl)
    assert s.label == "periodic" and s.backend == "compiled"


def test_stated_case_compiled_sum_rule():
    s = compiled(REF, periods=200, transient=300, warmup=100)
    per_period, total = check_sum_rule(s)
    assert per_period <= SUM_RULE_TOL and total <= SUM_RULE_TOL, (per_period, total)


def test_chaotic_walks_share_their_events_until_rounding_grows():
    """Gap -16 from the paper's step 1: the two walks see the same events period by period
    (the same impacts, the same growths) until rounding, amplified by e^0.83 a period, parts
    the motions; over the first 10 periods the sections differ by less than 1e-8."""
    p = REF.replace(gap=-16.0)
    run = dict(periods=10, transient=0, warmup=0, blocks=2)
    c, r = compiled(p, **run), reference(p, **run)
    assert c.impacts == r.impacts and c.captures == r.captures
    assert np.max(np.abs(c.sections - r.sections)) <= 1e-8 * p.x_st * p.omega
    finite = np.isfinite(r.increments).all(axis=0)
    assert np.max(np.abs(c.increments[:, finite] - r.increments[:, finite])) <= 1e-6


@pytest.mark.parametrize("backend", ["compiled", pytest.param("python", marks=pytest.mark.slow)])
def test_the_clock_is_rebased_only_clear_of_the_stop(backend):
    """Regression: at gap -23.68 of the gap sweep (a chatter cycle, from the sweep's own start
    state) a lift-off falls 4e-7 T before the 100th section; re-based there, the walk restarted
    on the stop within the grazing resolution, lost the lift-off's departure and spent the
    solver's work bound at once. The re-basing now waits for a section clear of the stop."""
    from impactdamper.studies.lyapunov.sweep import start_state

    with open(ROOT / "figures" / "sweep_gap.csv") as f:
        row = next(r for r in csv.DictReader(f) if r["direction"] == "up" and r["index"] == "215")
    p = REF.replace(gap=float(row["value"]))
    assert p.gap == -23.68
    s = idp.lyapunov_spectrum(p, state=start_state(p, row), transient=100, warmup=50, periods=200, backend=backend)
    assert s.label == "periodic" and s.captures > 0 and s.dimension == 2


def test_a_walk_error_is_never_a_root():
    assert ERR_WALK > MARCH_ROOT


@pytest.mark.slow
def test_where_the_kernels_do_not_apply_the_reference_walks_and_says_so():
    """A double root of eq. (4) has no modal form: the reference walks (the matrix
    exponential), the result says why."""
    from impactdamper.studies.performance.hardcases import _hard_cases

    delta2 = {h.name: h for h in _hard_cases()}["repeated_roots"].changes["delta2"]
    p = idp.Parameters(N=0.9, delta2=delta2)
    run = dict(periods=20, transient=20, warmup=10, blocks=2)
    c = compiled(p, **run)
    assert (c.backend, c.fallback) == ("python", "matrix_exponential")
    np.testing.assert_array_equal(c.exponents, reference(p, **run).exponents)


@pytest.mark.slow
def test_the_work_bound_ends_a_compiled_walk_with_the_references_error():
    """A motion far faster than the forcing (theta = 1e-7) reaches the event loop's work bound
    within its first period: the compiled walk stops there with the reference's named error."""
    from impactdamper.core.events import SearchLimitError

    with pytest.raises(SearchLimitError, match=r"^`theta` = 1e-07 is beyond what the solver resolves"):
        compiled(REF.replace(theta=1e-7), periods=10, transient=0, warmup=0, blocks=2)


def test_free_scales_do_not_change_the_compiled_exponents():
    """Other units, and units outside the kernels' native range (solved in the reference case's
    units): the same exponents per period."""
    run = dict(periods=100, transient=100, warmup=20)
    r = compiled(REF, **run)
    for q in (REF.replace(x_st=2.5, m1=3.0, omega=7.0), REF.replace(x_st=1e-40)):
        s = compiled(q, **run)
        assert s.backend == "compiled" and s.fallback == ""
        np.testing.assert_allclose(s.exponents, r.exponents, rtol=0, atol=1e-9)


# ----------------------------------------------------------------------------------------
# Labels of the many-point call
# ----------------------------------------------------------------------------------------
def test_many_point_call_labels_its_nonperiodic_points():
    """With classify, a point left nonperiodic gets its spectrum's label from the section its
    run hands on (chaotic at -16, quasi-periodic past the Neimark-Sacker point at -10.2); a
    periodic point none. Without it, no label (the default keeps existing records). (Without
    the rescue, which tries Newton at every period up to 8 and takes seconds here.)"""
    points = [[-16.0], [-10.2], [-5.8]]
    settings = SweepSettings(continuation=False, rescue=False, classify=True)
    res = idp.steady_states(REF, ("gap",), points, settings=settings, chain=False)
    assert res.regime.tolist()[:2] == ["nonperiodic", "nonperiodic"]
    assert res.lyapunov_label.tolist() == ["chaotic", "quasi-periodic", ""]
    assert res.lyapunov_exponent[0] > SIGNIFICANCE * res.lyapunov_error[0] + ZERO_BAND
    assert abs(res.lyapunov_exponent[1]) + SIGNIFICANCE * res.lyapunov_error[1] <= ZERO_BAND
    assert math.isnan(res.lyapunov_exponent[2])
    plain = idp.steady_states(REF, ("gap",), points, settings=SweepSettings(rescue=False), chain=False)
    assert plain.lyapunov_label.tolist() == ["", "", ""]
    assert np.array_equal(plain.regime_code, res.regime_code)


@pytest.mark.slow
def test_labels_follow_the_rescue():
    """With the rescue (which finds no stable cycle at these points), the points it leaves
    nonperiodic are labelled as without it."""
    settings = SweepSettings(continuation=False, classify=True)
    res = idp.steady_states(REF, ("gap",), [[-16.0], [-10.2]], settings=settings, chain=False)
    assert res.regime.tolist() == ["nonperiodic", "nonperiodic"] and res.fallbacks == {}
    assert res.lyapunov_label.tolist() == ["chaotic", "quasi-periodic"]


@pytest.mark.parametrize("bad", [0, 1001, 2.5, True, -10])
def test_classify_periods_is_checked(bad):
    with pytest.raises(ValueError, match="^`classify_periods`"):
        SweepSettings(classify_periods=bad)


# ----------------------------------------------------------------------------------------
# The command
# ----------------------------------------------------------------------------------------
# The keys the command's --json prints (its help's epilog documents them).
JSON_KEYS = {
    "exponents",
    "exponents_per_second",
    "errors",
    "spreads",
    "label",
    "halves",
    "half_errors",
    "settled_period",
    "settled_since",
    "window",
    "significance",
    "zero_band",
    "dimension",
    "periods",
    "transient",
    "warmup",
    "blocks",
    "impacts",
    "captures",
    "liftoffs",
    "grazing",
    "contact_time",
    "method",
    "backend",
    "fallback",
    "parameters",
}


def test_command_answers_in_json(capsys):
    assert main(["lyapunov", "--gap", "-16", "--periods", "500", "--transient", "200", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == JSON_KEYS
    assert out["label"] in LABELS and out["label"] == "chaotic" and out["backend"] == "compiled"
    assert out["exponents"][0] > 0.5 and out["parameters"]["gap"] == -16.0
    assert all(key in LYAPUNOV_KEYS for key in JSON_KEYS)  # the command's epilog names every key


def test_command_prints_the_label(capsys):
    assert main(["lyapunov", "--periods", "200", "--transient", "100", "--warmup", "50"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("periodic: exponents per forcing period -0.34067")


@pytest.mark.parametrize(
    "argv, flag",
    [
        (["--periods", "1001"], "--periods"),
        (["--transient", "-1"], "--transient"),
        (["--warmup", "x"], "--warmup"),
        (["--state", "0", "1", "2", "3"], "--state"),
        (["--backend", "numba"], "--backend"),
        (["--t0", "nan"], "--t0"),
    ],
)
def test_command_names_a_bad_flag(argv, flag, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["lyapunov", *argv])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"argument {flag}" in err, err


# ----------------------------------------------------------------------------------------
# More periodic orbits, the gap sweep's nonperiodic bands, the sum rule on chaos
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("gap, k, z", [(-9.6, 2, 3), (-14.0, 1, 2), (14.0, 1, 0)])
def test_other_stable_orbits_compiled_match_floquet_multipliers(gap, k, z):
    p = REF.replace(gap=gap)
    o = idp.solve_orbit(p)
    assert (o.period_multiple, len(o.impacts)) == (k, z)
    s = compiled(p)
    fl = floquet_exponents(p)
    assert np.max(np.abs(s.exponents - fl)) <= FLOQUET_TOL, (s.exponents, fl)
    assert s.label == "periodic"


def sweep_np_values() -> dict:
    """The committed gap sweep's nonperiodic values per direction (figures/sweep_gap.csv)."""
    with open(ROOT / "figures" / "sweep_gap.csv") as f:
        rows = list(csv.DictReader(f))
    return {
        d: {round(float(r["value"]), 6) for r in rows if r["direction"] == d and r["label"] == "np"}
        for d in ("up", "down")
    }


# Points of the gap sweep's np bands (each np in the committed sweep, checked below), the
# first two in the bands of impacts only, the third with captures and lift-offs.
NP_POINTS = [-19.024, -16.0, -17.008, -12.016]


@pytest.mark.parametrize("gap", [g if g == -16.0 else pytest.param(g, marks=pytest.mark.slow) for g in NP_POINTS])
def test_np_points_largest_exponent_against_benettin(gap):
    """The compiled largest exponent against Benettin's estimate made with the compiled
    solver's stroboscopic map alone (no saltation matrices): along the same motion, per
    period, to SAME_MOTION_TOL; on the next 2000 periods of the attractor, within SIGNIFICANCE
    combined standard errors plus Benettin's rounding floor."""
    assert any(gap in values for values in sweep_np_values().values()), gap
    p = REF.replace(gap=gap)
    s = compiled(p)
    # positive beyond its error and unsettled; chaotic where the window's halves agree (at -19.024
    # on this machine they differ by 5 combined errors, 1.165 against 1.089: "not settled", a
    # verdict on a chaotic run's last digits, so either is allowed there)
    assert s.exponents[0] > SIGNIFICANCE * s.errors[0] and s.settled is None, (s.exponents, s.errors)
    assert s.label == "chaotic" if gap == -16.0 else s.label in ("chaotic", "not settled"), (s.label, s.halves)
    step = get_backend("compiled")[0].map_step(p, Tolerances())
    one = lambda y: step(y, 1)[0]  # noqa: E731 (the state one period on, t0 = 0)
    assert s.t_section == 0.0
    same = benettin(p, 0.0, s.sections[0], s.periods - 1, along=s.sections, step=one)
    skip = 50
    assert abs(same[skip:].mean() - s.increments[skip:-1, 0].mean()) <= SAME_MOTION_TOL
    lam, err = block_estimate(benettin(p, 0.0, one(s.sections[-1]), s.periods, step=one))
    combined = math.hypot(err, s.errors[0])
    assert abs(lam - s.exponents[0]) <= SIGNIFICANCE * combined + BENETTIN_FLOOR, (lam, err, s.exponents[0])


@pytest.mark.slow
@pytest.mark.parametrize("gap", [-19.0, -16.0])
def test_sum_rule_chaotic_compiled(gap):
    s = compiled(REF.replace(gap=gap))
    assert s.label == "chaotic" and s.captures == 0
    per_period, total = check_sum_rule(s)
    assert per_period <= SUM_RULE_TOL and total <= SUM_RULE_TOL, (per_period, total)


@pytest.mark.slow
def test_chaotic_backends_agree_within_their_errors():
    """Gap -16: the two walks part after ~20 periods (rounding, amplified), so their exponents
    are two estimates on the same attractor: within SIGNIFICANCE combined standard errors."""
    p = REF.replace(gap=-16.0)
    c, r = compiled(p), reference(p)
    assert c.label == r.label == "chaotic"
    for i in range(4):
        assert abs(c.exponents[i] - r.exponents[i]) <= SIGNIFICANCE * math.hypot(c.errors[i], r.errors[i]), i


@pytest.mark.slow
def test_torus_compiled():
    s = compiled(REF.replace(gap=-10.2))
    assert s.label == "quasi-periodic", (s.exponents, s.errors)
    assert abs(s.exponents[0]) <= ZERO_BAND / 10
