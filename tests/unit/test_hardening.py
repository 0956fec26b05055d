"""Every extreme or bad input gets the right answer or a one-line error naming the
argument: no traceback, no hang (the solver's work bounds end every case), no silently wrong
result.

Property-based tests (Hypothesis) draw parameters, tolerances and command-line arguments across
and beyond their domains and check

* a classification (one of ``REGIMES``) or a clean named error (``TypeError``/``ValueError``
  naming an argument in backticks, ``SearchLimitError`` naming a parameter), in one line
  (how long a case takes is measured by the benchmarks, not asserted here);
* results invariant under the free scales x_st, m1 and omega and under the start time t0
  (the forcing's phase aside);
* no NaN in any output.

They are deterministic (``derandomize=True``, no example database) and sized for CI: the file
runs in well under 90 s on one core. ``IMPACTDAMPER_HARDENING_EXAMPLES`` raises the number of
examples for a deeper local search. The regression tests at the end name the inputs the
issue's probe found.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import impactdamper as idp
from impactdamper.cli import main
from impactdamper.core.events import SearchLimitError
from impactdamper.core.parameters import PARAMETER_TABLE

REF = idp.Parameters()
SIMULATE = sys.modules["impactdamper.core.simulate"]  # (the package's `simulate` is the function)
EXAMPLES = int(os.environ.get("IMPACTDAMPER_HARDENING_EXAMPLES", "0")) or None
PROPERTY = settings(
    derandomize=True,
    database=None,
    deadline=None,
    max_examples=EXAMPLES or 50,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
# Names an error may point at: the parameters and the functions' own arguments.
ARGUMENTS = set(idp.Parameters.names()) | {
    "p",
    "t0",
    "t_end",
    "t_target",
    "state",
    "tolerances",
    "gap_tol",
    "chatter_tol",
    "force_tol",
    "settle_tol",
    "max_periods",
    "max_period_multiple",
    "period_multiple",
    "seed",
    "bounds",
    "max_points",
    "step",
    "min_step",
    "max_step",
    "direction",
    "parameter",
    "orbit",
    "times",
    "states_after",
}


@contextlib.contextmanager
def small_work_bound():
    """The solver's work bound cut 10-fold, so that drawn cases beyond it end in seconds (the
    default bound is checked by the regression tests below)."""
    saved = SIMULATE.STEPS_AT_START, SIMULATE.STEPS_PER_PERIOD
    SIMULATE.STEPS_AT_START = SIMULATE.STEPS_PER_PERIOD = 2000
    try:
        yield
    finally:
        SIMULATE.STEPS_AT_START, SIMULATE.STEPS_PER_PERIOD = saved


def assert_named_error(err: BaseException) -> None:
    """One line, naming an argument in backticks (numpydoc/scipy style)."""
    message = str(err)
    assert "\n" not in message, message
    names = re.findall(r"`([A-Za-z_0-9]+)`", message)
    assert names and names[0] in ARGUMENTS, message


def assert_no_nan(obj, where: str = "") -> None:
    if isinstance(obj, float):
        assert not math.isnan(obj), where
    elif isinstance(obj, dict):
        for k, v in obj.items():
            assert_no_nan(v, f"{where}.{k}")
    elif isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            assert_no_nan(v, f"{where}[{i}]")


def outcome(call):
    """(result, None) or (None, error) for an expected error type. (The solver's work bounds end
    a drawn case; how long that takes is the benchmarks' business, not a test's.)"""
    try:
        result, err = call(), None
    except (TypeError, ValueError, SearchLimitError) as e:
        result, err = None, e
    if isinstance(err, idp.OrbitError):  # an answer, not a bad input: Newton failed, or no closed-form orbit
        assert "\n" not in str(err)
    elif err is not None:
        assert_named_error(err)
    return result, err


# --- strategies: values across and beyond each domain -----------------------------------------
SPECIAL = [0.0, -0.0, -1.0, 1e-300, 1e300, 5e-324, math.nan, math.inf, -math.inf, 1e-12, 1e12]


def wide_positive(lo: float = -12, hi: float = 12):
    """10^u for u uniform in [lo, hi] (a log-uniform draw), plus special values."""
    return st.one_of(st.floats(lo, hi).map(lambda u: 10.0**u), st.sampled_from(SPECIAL))


def parameter_value(name: str):
    typical = getattr(REF, name)
    near = st.floats(0.2, 5.0).map(lambda f: typical * f)
    if name == "R":
        return st.one_of(st.floats(-0.5, 1.5), st.sampled_from([0.0, 1.0, math.nan]))
    if name == "gap":
        return st.one_of(st.floats(-50.0, 30.0), st.sampled_from([0.0, -1e6, 1e6, math.nan, math.inf]))
    if name in ("delta1", "delta2"):
        return st.one_of(near, st.just(0.0), wide_positive(-15, 7))
    return st.one_of(near, wide_positive())


# Most examples change a few parameters, so that the reference's neighbourhood is explored too.
parameter_changes = st.fixed_dictionaries({}, optional={name: parameter_value(name) for name in idp.Parameters.names()})
bad_types = st.sampled_from([None, "1.0", True, [1.0], 1 + 2j, np.bool_(False)])


@st.composite
def parameters(draw):
    changes = draw(parameter_changes)
    try:
        return idp.Parameters(**changes)
    except (TypeError, ValueError) as err:
        assert_named_error(err)
        assume(False)


# --- properties ---------------------------------------------------------------------------------
@PROPERTY
@given(
    changes=parameter_changes, bad=st.one_of(st.none(), st.tuples(st.sampled_from(idp.Parameters.names()), bad_types))
)
def test_parameters_construct_or_raise_one_named_line(changes, bad):
    if bad is not None:
        changes = {**changes, bad[0]: bad[1]}
    p, err = outcome(lambda: idp.Parameters(**changes))
    if p is not None:
        assert all(type(getattr(p, n)) is float and math.isfinite(getattr(p, n)) for n in p.names())
        for derived in ("omega1", "omega2", "m2", "c1", "c2", "P0", "T", "reduced_mass"):
            assert math.isfinite(getattr(p, derived)) and getattr(p, derived) > 0.0, derived


@PROPERTY
@given(
    p=parameters(),
    gap_tol=st.one_of(
        st.just(1e-12),
        st.floats(-16, -0.01).map(lambda u: 10.0**u),
        st.sampled_from([0.0, 1.0, 10.0, -1e-12, math.nan, math.inf]),
        bad_types,
    ),
)
def test_algorithm1_answers_or_names_the_problem(p, gap_tol):
    r, err = outcome(lambda: idp.algorithm1(p, gap_tol=gap_tol))
    if r is not None:
        d = r.to_dict()
        assert_no_nan(d)
        json.dumps(d, allow_nan=False)
        if r.exists:
            assert 0.0 <= r.impact_phase < 1.0 and r.S > 0.0
            assert all(0.0 <= a <= b <= 1.0 for a, b in r.negative_gap_intervals)


# Solver arguments: valid ones from wide ranges, and now and then one bad value among them.
BAD_SOLVER_ARGUMENTS = {
    "t0": [math.nan, math.inf, "0", None],
    "gap_tol": [0.0, 1.0, 10.0, math.nan, -1e-12, "1e-12"],
    "settle_tol": [0.0, 2.0, math.nan, True],
    "max_periods": [1, -2, True, 2.5, 10**7, np.int64(0)],
    "max_period_multiple": [0, True, 2.0, 10**6],
    "state": [[0.0] * 3, [math.nan] * 4, [1e300, 0, 0, 0], "0 0 0 0"],
}


@st.composite
def solver_arguments(draw, p: idp.Parameters) -> dict:
    g = draw(st.one_of(st.just(0.0), st.floats(0.0, 30.0), wide_positive(-12, 11).filter(math.isfinite)))
    x1, v1, v2 = (draw(st.one_of(st.floats(-30.0, 30.0), st.sampled_from([0.0, 1e-300, -1e11]))) for _ in range(3))
    state = [x1 * p.x_st, (x1 - g) * p.x_st + p.Delta0, v1 * p.x_st * p.omega, v2 * p.x_st * p.omega]
    kwargs = {
        "t0": draw(st.one_of(st.just(0.0), st.floats(-1e3, 1e3), st.sampled_from([1e5, 1e16, 1e20, -1e300]))),
        "state": draw(st.one_of(st.none(), st.just(state))),
        "gap_tol": draw(st.one_of(st.just(1e-12), st.floats(-16, -0.01).map(lambda u: 10.0**u))),
        "settle_tol": draw(st.one_of(st.just(1e-10), st.floats(-16, -0.01).map(lambda u: 10.0**u))),
        "max_periods": draw(st.sampled_from([2, 7, 300, 800, 800, 1500])),
        "max_period_multiple": draw(st.integers(1, 8)),
    }
    kwargs["max_period_multiple"] = min(kwargs["max_period_multiple"], kwargs["max_periods"] - 1)
    if draw(st.integers(0, 3)) == 3:  # (not 0: Hypothesis leans to the simplest draws)
        name = draw(st.sampled_from(sorted(BAD_SOLVER_ARGUMENTS)))
        kwargs[name] = draw(st.sampled_from(BAD_SOLVER_ARGUMENTS[name]))
    return kwargs


@pytest.mark.slow
@settings(PROPERTY, max_examples=EXAMPLES or 100)
@given(data=st.data())
def test_steady_state_classifies_or_names_the_problem(data):
    p = data.draw(parameters())
    kwargs = data.draw(solver_arguments(p))

    def call():
        rest = {k: v for k, v in kwargs.items() if k != "gap_tol"}
        return idp.steady_state(p, tolerances=idp.Tolerances(gap_tol=kwargs["gap_tol"]), **rest, backend="python")

    with small_work_bound():
        s, err = outcome(call)
    if s is not None:
        assert s.regime in idp.REGIMES
        d = s.to_dict()
        assert_no_nan(d)
        assert 0.0 <= d["contact_fraction"] <= 1.0 and math.isfinite(d["x1_max"])
        assert all(0.0 <= i["phase"] < 1.0 for i in d["impacts"])


@PROPERTY
@given(
    p=parameters(),
    seed=st.sampled_from(["auto", "auto", "alg1", "simulate", "simulate", "nonsense", None]),
    period_multiple=st.one_of(st.none(), st.sampled_from([1, 2, 3, 0, -1, True, 10**6, 1.5])),
)
def test_solve_orbit_solves_or_names_the_problem(p, seed, period_multiple):
    def call():
        return idp.solve_orbit(p, seed, period_multiple=period_multiple, max_periods=60)

    with small_work_bound():
        o, err = outcome(call)
    if o is not None:
        assert o.regime in idp.REGIMES
        assert_no_nan(o.to_dict())


# Robust cases (away from bifurcations) whose settled motion must not depend on the free scales
# or the start time: one impact, a 3-impact 2T cycle, chatter, no contact, persistent contact.
ROBUST_GAPS = [-5.8, -10.0, -13.0, 20.0, -35.0]


def assert_same_motion(a: idp.SteadyState, b: idp.SteadyState) -> None:
    da, db = a.to_dict(), b.to_dict()
    assert (da["regime"], da["period_multiple"], da["impacts_per_cycle"]) == (
        db["regime"],
        db["period_multiple"],
        db["impacts_per_cycle"],
    )
    assert db["x1_max"] == pytest.approx(da["x1_max"], rel=1e-7)
    assert db["contact_fraction"] == pytest.approx(da["contact_fraction"], abs=1e-7)
    for ia, ib in zip(da["impacts"], db["impacts"]):
        assert abs((ia["phase"] - ib["phase"] + 0.5) % 1.0 - 0.5) < 1e-7
        assert ib["t_over_T"] == pytest.approx(ia["t_over_T"], abs=1e-7)
        # (Absolute in x_st omega: the last bounces of a chatter sequence are slow and their
        # relative velocities carry the rounding of the whole sequence.)
        assert ib["velocity_rel"] == pytest.approx(ia["velocity_rel"], rel=1e-6, abs=1e-7)
        assert ib["impulse_rel"] == pytest.approx(ia["impulse_rel"], rel=1e-6, abs=1e-7)


_BASELINE: dict = {}


def baseline(gap: float) -> idp.SteadyState:
    if gap not in _BASELINE:
        _BASELINE[gap] = idp.steady_state(REF.replace(gap=gap), backend="python")
    return _BASELINE[gap]


@settings(PROPERTY, max_examples=EXAMPLES or 20)
@given(
    gap=st.sampled_from(ROBUST_GAPS),
    x_st=st.floats(-250, 250).map(lambda u: 10.0**u),
    m1=st.floats(-250, 250).map(lambda u: 10.0**u),
    omega=st.floats(-5, 5).map(lambda u: 10.0**u),
    t0=st.one_of(st.floats(-1e4, 1e4), st.sampled_from([1e5, 1e15, 1e16, 1e20, 1e300, -1e300])),
)
def test_settled_motion_does_not_depend_on_scales_or_start_time(gap, x_st, m1, omega, t0):
    try:
        p = REF.replace(gap=gap, x_st=x_st, m1=m1, omega=omega)
    except ValueError as err:  # the dimensional units themselves overflow: a named error
        assert_named_error(err)
        assume(False)
    s, err = outcome(lambda: idp.steady_state(p, t0=t0, backend="python"))
    assert err is None, err
    assert_same_motion(baseline(gap), s)
    assert s.p == p and s.trajectory.model.p == p
    # Dimensional values are the relative ones in the user's units.
    for imp, rel in zip(s.impacts, s.to_dict()["impacts"]):
        assert imp.velocity == pytest.approx(rel["velocity_rel"] * x_st * omega, rel=1e-12)


@settings(PROPERTY, max_examples=EXAMPLES or 40)
@given(
    gap=st.floats(-14.0, 14.0),
    x_st=st.floats(-300, 300).map(lambda u: 10.0**u),
    m1=st.floats(-300, 300).map(lambda u: 10.0**u),
)
def test_algorithm1_does_not_depend_on_scales(gap, x_st, m1):
    try:
        p = REF.replace(gap=gap, x_st=x_st, m1=m1)
    except ValueError as err:
        assert_named_error(err)
        assume(False)
    a, b = idp.algorithm1(REF.replace(gap=gap)), idp.algorithm1(p)
    assert a.exists == b.exists and a.admissible == b.admissible
    if a.exists:
        assert abs((a.impact_phase - b.impact_phase + 0.5) % 1.0 - 0.5) < 1e-9
        assert b.S / (m1 * x_st * p.omega) == pytest.approx(a.S / (REF.m1 * REF.x_st * REF.omega), rel=1e-9)
        assert b.min_gap == pytest.approx(a.min_gap, rel=1e-9, abs=1e-12)


FLAGS = ["--" + n.replace("_", "-") for n in idp.Parameters.names()] + [
    "--t0",
    "--settle-tol",
    "--max-periods",
    "--max-period-multiple",
    "--gap-tol",
    "--chatter-tol",
]
FLAG_VALUES = st.one_of(
    st.sampled_from(
        [
            "nan",
            "inf",
            "-inf",
            "1e400",
            "-1e400",
            "abc",
            "",
            "0",
            "-0",
            "1e-320",
            "1e-300",
            "1e300",
            "True",
            "0x10",
            "1_000",
            "2.5",
            "-1",
            "1e16",
            "1e20",
        ]
    ),
    st.floats(-1e3, 1e3).map(repr),
    st.integers(-5, 5000).map(str),
)


@PROPERTY
@given(
    command=st.sampled_from(["steady", "alg1", "orbit"]),
    flags=st.lists(st.tuples(st.sampled_from(FLAGS), FLAG_VALUES), max_size=3),
)
def test_command_line_prints_json_or_one_error_line(command, flags):
    argv = [command, "--json"]
    for flag, value in flags:
        if command == "alg1" and flag not in FLAGS[:10]:
            continue  # (alg1 has no solver flags: argparse would reject them, also a one-line error)
        argv += [flag + "=" + value]
    out, err = io.StringIO(), io.StringIO()
    with small_work_bound(), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = main(argv)
        except SystemExit as exit_:
            status = exit_.code
    if status == 0:
        d = json.loads(out.getvalue(), parse_constant=lambda c: pytest.fail(f"{c} in the JSON"))
        assert d.get("regime", "single_impact") in idp.REGIMES
        assert err.getvalue() == ""
    else:
        assert status in (1, 2), status  # 1: the direct solve did not converge (orbit), else 2
        assert out.getvalue() == ""
        assert err.getvalue().count("\n") == 1, err.getvalue()


# --- regressions: the inputs a probe of extremes found ---------------------------------------------
def run(*args: str, timeout: float = 60) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "impactdamper", *args], capture_output=True, text=True, timeout=timeout
    )


def steady_json(*args: str) -> dict:
    proc = run("steady", *args, "--json")
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    return json.loads(proc.stdout)


REFERENCE_PHASE = idp.algorithm1(REF).impact_phase


@pytest.mark.parametrize(
    "args",
    [
        ("--t0", "1e5"),
        ("--omega", "1000", "--t0", "1000"),
        ("--t0", "1e15"),
        ("--t0", "1e16"),
        ("--t0", "1e20"),
        ("--t0", "-7.5"),
        ("--x-st", "1e-200"),
        ("--x-st", "1e200"),
        ("--m1", "1e-300"),
        ("--m1", "1e300"),
    ],
)
def test_reference_answer_whatever_the_start_time_and_scales(args):
    # Were nonperiodic (t0 1e5, omega 1000 t0 1000), no_contact (t0 1e20, x_st 1e-200), a
    # traceback (t0 1e16), hangs (t0 1e15, x_st 1e200) and nonperiodic with S = 0 (m1 1e-300).
    d = steady_json(*args)
    assert (d["regime"], d["period_multiple"]) == ("single_impact", 1)
    assert d["x1_max"] == pytest.approx(5.5619, abs=1e-4)
    assert abs((d["impacts"][0]["phase"] - REFERENCE_PHASE + 0.5) % 1.0 - 0.5) < 1e-8


@pytest.mark.slow
@pytest.mark.parametrize(
    "command, args, flag, words",
    [
        ("alg1", ("--theta", "1.0131335798012997", "--delta1", "0", "--delta2", "0"), "--theta", "undamped resonance"),
        (
            "steady",
            ("--theta", "1.0131335798012997", "--delta1", "0", "--delta2", "0"),
            "--theta",
            "undamped resonance",
        ),
        ("orbit", ("--theta", "1.0131335798012997", "--delta1", "0", "--delta2", "0"), "--theta", "undamped resonance"),
        ("steady", ("--theta", "1.0131335798012997", "--delta1", "1e-12", "--delta2", "1e-12"), "--theta", "resonance"),
        ("alg1", ("--theta", "0.5065667899006499", "--delta1", "0", "--delta2", "0"), "--theta", "eq. 8"),
        ("steady", ("--theta", "1e-9"), "--theta", "work bound"),
        ("steady", ("--theta", "1e-6"), "--theta", "work bound"),
        ("orbit", ("--theta", "1e-9"), "--theta", "work bound"),
        ("steady", ("--delta1", "1e6", "--delta2", "1e6"), "--delta1", "work bound"),
        ("steady", ("--state", "1e300", "0", "0", "0"), "--state", "must be within 1e+12 x_st"),
        ("orbit", ("--state", "1e300", "0", "0", "0"), "--state", "must be within 1e+12 x_st"),
        ("steady", ("--mu", "1e-300"), "--mu", "beyond what the solver resolves"),
        ("steady", ("--mu", "1e300"), "--mu", "floating-point range"),
        ("steady", ("--theta", "1e-300"), "--theta", "c1"),
        ("steady", ("--max-periods", "10000000"), "--max-periods", "[2, 100000]"),
        ("steady", ("--max-period-multiple", "4000"), "--max-period-multiple", "[1, 3999]"),
        ("orbit", ("--seed", "alg1", "--state", "0", "-5.8", "1", "-1"), "--state", "not allowed with --seed alg1"),
        ("orbit", ("--seed", "alg1", "--t0", "1"), "--t0", "not allowed with --seed alg1"),
        ("orbit", ("--period-multiple", "100000"), "--period-multiple", "[1, 64]"),
    ],
)
def test_limits_are_one_named_line(command, args, flag, words):
    proc = run(command, *args, "--json")
    assert proc.returncode == 2 and proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and f"argument {flag}: " in lines[0] and words in lines[0], proc.stderr


def test_output_to_a_closed_pipe_or_a_full_disk_is_one_line():
    with subprocess.Popen(
        [sys.executable, "-m", "impactdamper", "steady", "--gap", "-10"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    ) as proc:
        proc.stdout.close()  # closed before anything is written
        err = proc.stderr.read()
        assert proc.wait(timeout=60) == 1
    assert err.splitlines() == ["impactdamper: error: cannot write the output: Broken pipe"]
    if os.path.exists("/dev/full"):
        for args in (("alg1", "--json"), ("steady", "-h")):
            with open("/dev/full", "w") as full:
                done = subprocess.run(
                    [sys.executable, "-m", "impactdamper", *args],
                    stdout=full,
                    stderr=subprocess.PIPE,
                    text=True,
                    timeout=60,
                )
            assert done.returncode == 1
            assert done.stderr.splitlines() == ["impactdamper: error: cannot write the output: No space left on device"]


@pytest.mark.parametrize(
    "call, name, kind",
    [
        (lambda: idp.Parameters(gap=10**400), "gap", ValueError),
        (lambda: idp.algorithm1(None), "p", TypeError),
        (lambda: idp.steady_state(None, backend="python"), "p", TypeError),
        (lambda: idp.solve_orbit(None), "p", TypeError),
        (lambda: idp.simulate(None, 1.0, backend="python"), "p", TypeError),
        (lambda: idp.steady_state(REF, tolerances="x", backend="python"), "tolerances", TypeError),
        (lambda: idp.steady_state(REF, t0="0", backend="python"), "t0", TypeError),
        (lambda: idp.steady_state(REF, max_period_multiple=True, backend="python"), "max_period_multiple", TypeError),
        (lambda: idp.steady_state(REF, max_periods=True, backend="python"), "max_periods", TypeError),
        (lambda: idp.steady_state(REF, settle_tol="1e-10", backend="python"), "settle_tol", TypeError),
        (lambda: idp.steady_state(REF, state="0 0 0 0", backend="python"), "state", TypeError),
        (lambda: idp.steady_state(REF, state=[1e300, 0, 0, 0], backend="python"), "state", ValueError),
        (lambda: idp.steady_state(REF, backend="numba"), "backend", ValueError),
        (lambda: idp.algorithm1(REF.replace(gap=-9.6), gap_tol=math.nan), "gap_tol", ValueError),
        (lambda: idp.algorithm1(REF.replace(gap=-9.6), gap_tol=10.0), "gap_tol", ValueError),
        (lambda: idp.algorithm1(REF, gap_tol="1e-12"), "gap_tol", TypeError),
        (lambda: idp.simulate(REF, 1e9, backend="python"), "t_end", ValueError),
        (lambda: idp.simulate(REF, 1.0, t0=math.nan, backend="python"), "t0", ValueError),
        (lambda: idp.simulate(REF, 1e16, t0=1e16 - 1.0, backend="python"), "t0", ValueError),
        (lambda: idp.EventDrivenSolver(REF.replace(x_st=1e-200)), "x_st", ValueError),
        (lambda: idp.solve_orbit(REF, "alg1", state=[0.0, -5.8, 1.0, -1.0]), "state", ValueError),
        (lambda: idp.solve_orbit(REF, period_multiple=10**6), "period_multiple", ValueError),
    ],
)
def test_api_errors_name_the_argument(call, name, kind):
    with pytest.raises(kind) as info:
        call()
    assert str(info.value).startswith(f"`{name}`"), str(info.value)
    assert "\n" not in str(info.value)


def test_numpy_scalars_are_numbers_everywhere():
    p = idp.Parameters(theta=np.float32(1.0), mu=np.float64(0.08), gap=np.int64(-10))
    s = idp.steady_state(
        p,
        t0=np.float32(0.0),
        max_periods=np.int64(4000),
        max_period_multiple=np.int32(4),
        settle_tol=np.float64(1e-10),
        tolerances=idp.Tolerances(gap_tol=np.float32(1e-12)),
        backend="python",
    )
    assert (s.regime, s.period_multiple) == ("multi_impact", 2)
    assert idp.algorithm1(p, gap_tol=np.float64(1e-12)).exists


@pytest.fixture(scope="module")
def reference_orbit() -> idp.PeriodicOrbit:
    return idp.solve_orbit(REF, "alg1")


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"bounds": (-12.0, 11.5), "max_points": 0}, "max_points"),
        ({"bounds": (-12.0, 11.5), "max_points": -1}, "max_points"),
        ({"bounds": (-12.0, 11.5), "max_points": 1.5}, "max_points"),
        ({"bounds": (-12.0, 11.5), "max_points": True}, "max_points"),
        ({"parameter": "R", "bounds": (0.5, 1.5)}, "bounds"),
        ({"parameter": "theta", "bounds": (-1.0, 2.0)}, "bounds"),
        ({"parameter": "delta1", "bounds": (-0.1, 0.1)}, "bounds"),
        ({"bounds": (-12.0, math.inf)}, "bounds"),
        ({"bounds": (-12.0, math.nan)}, "bounds"),
        ({"bounds": "x"}, "bounds"),
        ({"bounds": (-12.0, 11.5), "direction": True}, "direction"),
        ({"bounds": (-12.0, 11.5), "step": math.nan}, "step"),
    ],
)
def test_continue_orbit_checks_its_arguments(reference_orbit, kwargs, name):
    with pytest.raises(ValueError) as info:
        idp.continue_orbit(reference_orbit, **kwargs)
    assert str(info.value).startswith(f"`{name}`") and "\n" not in str(info.value)


@pytest.mark.parametrize("spec", [s for s in PARAMETER_TABLE if s.allowed], ids=lambda s: s.name)
def test_continue_orbit_bounds_keep_to_every_parameters_range(reference_orbit, spec):
    """Every parameter of the table with a range (a new one too: the range is read from its row,
    not from a second table) refuses bounds reaching below it, naming the range."""
    value = float(getattr(reference_orbit.p, spec.name))
    with pytest.raises(ValueError) as info:
        idp.continue_orbit(reference_orbit, spec.name, (-1.0, value + 1.0))
    message = str(info.value)
    assert message.startswith("`bounds` = (-1.0, ") and f"`{spec.name}` must be {spec.allowed}," in message


def test_continue_orbit_at_extreme_scales_is_the_reference_branch(reference_orbit):
    a = idp.continue_orbit(reference_orbit, "gap", (-6.0, -5.8), direction=-1, step=0.05, max_points=6)
    far = idp.solve_orbit(REF.replace(x_st=1e-200, m1=1e250), "alg1")
    b = idp.continue_orbit(far, "gap", (-6.0, -5.8), direction=-1, step=0.05, max_points=6)
    assert len(a.points) == len(b.points) > 2 and a.end_reason == b.end_reason
    assert [q.value for q in b.points] == pytest.approx([q.value for q in a.points], abs=1e-12)
    for qa, qb in zip(a.points, b.points):
        assert qb.phases == pytest.approx(qa.phases, abs=1e-12)
        assert qb.states_after[0][0] == pytest.approx(qa.states_after[0][0] * 1e-200, rel=1e-9)


def test_simulate_has_a_work_bound_and_rescales():
    with pytest.raises(ValueError, match=r"^`t_end` = 1000000000.0 is not allowed: .* max_periods = 100000"):
        idp.simulate(REF, 1e9, backend="python")
    # 6e5 s took 100 s: refused up front now (the bound, MAX_SIMULATE_PERIODS = 1e5 periods)
    with pytest.raises(ValueError, match=r"^`t_end` = 600000.0 is not allowed: .* max_periods = 100000"):
        idp.simulate(REF, 6e5)
    a = idp.simulate(REF, 5 * REF.T, backend="python")
    b = idp.simulate(REF.replace(x_st=1e-200), 5 * REF.T, backend="python")
    assert [e.kind for e in a.events] == [e.kind for e in b.events]
    assert [e.t for e in b.events] == pytest.approx([e.t for e in a.events], abs=1e-13)
    assert b.sample(2.0)[0] == pytest.approx(a.sample(2.0)[0] * 1e-200, rel=1e-9)
