"""Command line: ``python -m impactdamper steady|alg1 ... --json`` (run as a subprocess), and a
bad flag value exiting with status 2 and one line naming the flag."""

import io
import json
import math
import subprocess
import sys

import pytest

from helpers import heavy_modules_after, phase_difference

import impactdamper as idp
from impactdamper.cli import main
from impactdamper.cli import run as run_cli


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "impactdamper", *args], capture_output=True, text=True, timeout=120)


def test_steady_json_at_the_reference_gap():
    proc = run("steady", "--gap", "-5.8", "--json")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    d = json.loads(proc.stdout)
    for key in ("regime", "period_multiple", "impacts_per_cycle", "impacts", "contact_fraction", "x1_max"):
        assert key in d
    assert (d["regime"], d["period_multiple"], d["impacts_per_cycle"]) == ("single_impact", 1, 1)
    (imp,) = d["impacts"]
    assert {"t_over_T", "phase", "velocity", "impulse"} <= set(imp)
    assert imp["t_over_T"] == 0.0
    r = idp.algorithm1(idp.Parameters())
    assert abs(phase_difference(imp["phase"], r.impact_phase)) <= 1e-9
    assert imp["velocity"] == pytest.approx(r.velocity, rel=1e-8)
    assert imp["impulse"] == pytest.approx(r.S, rel=1e-8)
    assert d["contact_fraction"] == 0.0 and d["x1_max"] == pytest.approx(5.5619, abs=1e-4)
    s = idp.steady_state(idp.Parameters())  # the same call as the API's, its default backend
    assert (
        (d["method"], d["backend"], d["fallback"])
        == (s.method, s.backend, s.fallback)
        == ("simulation", "compiled", "")
    )
    assert d == json.loads(
        json.dumps({**s.to_dict(), "method": s.method, "backend": s.backend, "fallback": s.fallback})
    )


def test_steady_json_multi_impact_and_parameters_echoed():
    proc = run("steady", "--gap", "-10", "--m1", "37.5", "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert (d["regime"], d["period_multiple"], d["impacts_per_cycle"]) == ("multi_impact", 2, 3)
    assert [i["t_over_T"] for i in d["impacts"]] == sorted(i["t_over_T"] for i in d["impacts"])
    assert d["parameters"]["gap"] == -10.0 and d["parameters"]["m1"] == 37.5


def test_alg1_json():
    proc = run("alg1", "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    for key in ("exists", "eps", "S", "min_gap", "negative_gap_intervals"):
        assert key in d
    r = idp.algorithm1(idp.Parameters())
    assert d["exists"] is True and d["negative_gap_intervals"] == []
    assert d["eps"] == r.eps and d["S"] == r.S


def test_alg1_json_no_solution_is_valid_json():
    proc = run("alg1", "--gap", "-12", "--json")
    assert proc.returncode == 0
    d = json.loads(proc.stdout)  # NaN is not JSON: the CLI writes null
    assert d["exists"] is False and d["eps"] is None and d["S"] is None and "eq. (16)" in d["reason"]


@pytest.mark.parametrize(
    "args, flag",
    [
        (("steady", "--gap", "abc"), "--gap"),  # type error (argparse)
        (("alg1", "--R", "1.5"), "--R"),  # range error (Parameters)
        (("steady", "--x-st", "-1"), "--x-st"),
        (("steady", "--max-periods", "2.5"), "--max-periods"),
        (("steady", "--settle-tol", "2"), "--settle-tol"),  # range error (steady_state)
        (("steady", "--state", "0", "0", "0", "0"), "--state"),  # overlapping bodies
    ],
)
def test_bad_flag_exits_2_with_one_line(args, flag):
    proc = run(*args, "--json")
    assert proc.returncode == 2
    assert proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1
    assert f"argument {flag}:" in lines[0]


# The same rule for every flag, in-process (argparse exits through SystemExit).
BAD_IN_PROCESS = (
    [(name, "nan") for name in idp.Parameters.names()]
    + [(name, "x") for name in idp.Parameters.names()]
    + [(name, "0") for name in ("theta", "mu", "N", "omega", "x_st", "m1")]
    + [("delta1", "-1"), ("delta2", "-1"), ("R", "-0.1"), ("R", "1.1")]
)


@pytest.mark.parametrize("name, value", BAD_IN_PROCESS)
@pytest.mark.parametrize("command", ["steady", "alg1"])
def test_every_parameter_flag_is_checked(command, name, value, capsys):
    flag = "--" + name.replace("_", "-")
    with pytest.raises(SystemExit) as info:
        main([command, flag, value, "--json"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"argument {flag}:" in err


@pytest.mark.parametrize(
    "flag, value",
    [
        ("--gap-tol", "0"),
        ("--chatter-tol", "1"),
        ("--max-period-multiple", "0"),
        ("--t0", "inf"),
        ("--max-periods", "1"),
    ],
)
def test_solver_flags_are_checked(flag, value, capsys):
    with pytest.raises(SystemExit) as info:
        main(["steady", flag, value])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"argument {flag}:" in err


@pytest.mark.parametrize("theta", [["--theta", "1.2"], ["--theta=1.2"]])
def test_response_refuses_a_single_theta(theta, capsys):
    # The band sets theta: a --theta the command would ignore is an error, not a no-op.
    with pytest.raises(SystemExit) as info:
        main(["response", *theta, "--points", "2"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "argument --theta:" in err


def test_human_readable_output(capsys):
    assert main(["alg1", "--gap", "-10"]) == 0
    out = capsys.readouterr().out
    assert "not admissible" in out and "gap negative on (0.24" in out
    assert main(["steady", "--gap", "20"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("regime no_contact") and not math.isnan(float(out.split("= ")[-1].split()[0]))


# --- limits of the solver and of the output, each one line ---------------------------
def test_negative_exponent_values_are_numbers(capsys):
    # argparse took "-1e1" for an option ("expected one argument").
    assert main(["alg1", "--gap", "-1e1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"]["gap"] == -10.0


@pytest.mark.parametrize(
    "argv, flag",
    [
        (["orbit", "--seed", "alg1", "--state", "0", "-5.8", "1", "-1"], "--state"),
        (["orbit", "--seed", "alg1", "--t0", "0.1"], "--t0"),
    ],
)
def test_a_start_with_algorithm1s_orbit_is_a_usage_error(argv, flag, capsys):
    # --state was ignored silently: Algorithm No. 1's orbit is closed-form.
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"argument {flag}: not allowed with --seed alg1" in err


def test_work_bound_is_one_line_naming_the_parameter(monkeypatch, capsys):
    # A SearchLimitError reached the user as a traceback (theta = 1e-6, after 34-56 s).
    monkeypatch.setattr(sys.modules["impactdamper.core.simulate"], "STEPS_AT_START", 500)
    monkeypatch.setattr(sys.modules["impactdamper.core.simulate"], "STEPS_PER_PERIOD", 500)
    with pytest.raises(SystemExit) as info:
        # (1e-3 settles now, stuck, before the bound: its cycle is described on a settled stretch,
        # no longer on the start's transient.)
        main(["steady", "--theta", "1e-5", "--json"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "argument --theta: `theta` = 1e-05 is beyond what the solver resolves" in err
    assert "work bound" in err


def test_undamped_resonance_is_one_line_naming_theta(capsys):
    with pytest.raises(SystemExit) as info:
        main(["alg1", "--theta", "1.0131335798012997", "--delta1", "0", "--delta2", "0"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "argument --theta:" in err and "undamped resonance" in err


@pytest.mark.parametrize("N", ["1e-12", "1e-6"])
def test_a_suppressor_spring_too_soft_for_algorithm1_names_N(N, capsys):
    # A root of the free motion at zero (no spring brings the suppressor back): the message named
    # theta, which the user had not changed.
    with pytest.raises(SystemExit) as info:
        main(["alg1", "--N", N])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"argument --N: `N` = {float(N)!r} is not allowed" in err and "raise N" in err


@pytest.mark.parametrize("R", ["1", "0.99999999999"])
def test_no_loss_at_all_names_R_not_theta(R, capsys):
    # Undamped, Algorithm No. 1's denominator (eq. 15) is (1 - R)/2 at every theta: the message
    # said "move theta", which cannot help.
    with pytest.raises(SystemExit) as info:
        main(["alg1", "--R", R, "--delta1", "0", "--delta2", "0", "--theta", "1.37"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"argument --R: `R` = {float(R)!r} is not allowed" in err and "lower R" in err


class _Closed(io.StringIO):
    def write(self, text):
        raise BrokenPipeError(32, "Broken pipe")

    def flush(self):
        raise BrokenPipeError(32, "Broken pipe")


@pytest.mark.parametrize("argv", [["alg1", "--json"], ["alg1"], ["steady", "-h"]])
def test_output_that_cannot_be_written_is_one_line_and_status_1(argv, monkeypatch, capsys):
    # A closed pipe (`| head -c 1`) or a full disk (`> /dev/full`) ended in a traceback.
    monkeypatch.setattr(sys, "stdout", _Closed())
    assert run_cli(argv) == 1
    assert capsys.readouterr().err == "impactdamper: error: cannot write the output: Broken pipe\n"


@pytest.mark.parametrize(
    "args",
    [
        ("steady", "--x-st", "1e-200"),
        ("steady", "--m1", "1e300"),
        ("steady", "--t0", "1e20"),
        ("alg1", "--x-st", "1e200"),
        ("orbit", "--m1", "1e-300"),
    ],
)
def test_free_scales_and_start_time_do_not_change_the_answer(args, capsys):
    assert main([*args, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert main([args[0], "--json"]) == 0
    ref = json.loads(capsys.readouterr().out)
    if args[0] == "alg1":
        assert d["impact_phase"] == ref["impact_phase"] and d["min_gap"] == ref["min_gap"]
        return
    assert (d["regime"], d["period_multiple"]) == (ref["regime"], ref["period_multiple"]) == ("single_impact", 1)
    assert d["impacts"][0]["velocity_rel"] == pytest.approx(ref["impacts"][0]["velocity_rel"], rel=1e-9)
    assert abs(d["impacts"][0]["phase"] - ref["impacts"][0]["phase"]) < 1e-9


# --- messages name the cause --------------------------------------------------------------------
@pytest.mark.parametrize(
    ("argv", "words"),
    [
        # blamed --max-period-multiple, a flag never given
        (
            ["steady", "--max-periods", "2"],
            "argument --max-periods: `max_periods` = 2 is not allowed: must exceed "
            "--max-period-multiple = 8 (its default)",
        ),
        (["steady", "--max-periods", "3"], "argument --max-periods:"),
        (["steady", "--max-period-multiple", "4000"], "argument --max-period-multiple: `max_period_multiple` = 4000"),
        (["steady", "--max-periods", "5", "--max-period-multiple", "6"], "argument --max-periods: `max_periods` = 5"),
        # argparse's "expected one argument" for values that float() reads
        (["steady", "--gap", "-Infinity"], "argument --gap: `gap` = -inf is not allowed: must be a finite number"),
        (["steady", "--gap", "-nan"], "argument --gap: `gap` = nan is not allowed: must be a finite number"),
        (["steady", "--gap", "-1e-3x"], "argument --gap: expected one argument: a value that starts with '-'"),
    ],
)
def test_message_names_the_flag_given(argv, words, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err, err


def test_negative_number_with_digit_groups_is_a_value(capsys):
    """``--gap -1_000`` got argparse's "expected one argument"; float() reads it as -1000."""
    assert main(["steady", "--gap", "-1_000", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["parameters"]["gap"] == -1000.0 and d["regime"] == "stuck"


def test_work_bound_in_a_chatter_sequence_names_chatter_tol(capsys):
    """``steady --chatter-tol 1e-300 --gap -28`` blamed --gap; then its answer depended on the
    CPU (the compiled kernels settled a chatter cycle whose last impact had velocity 0.0 by
    round-off, the Python backend reached the work bound). A chatter_tol below the rounding of
    the state is refused up front, naming the floor; a work bound met in a chatter sequence at an
    allowed chatter_tol below its default still names chatter_tol (the message's choice, decided
    on counts, not on the last bits)."""
    floor = sys.modules["impactdamper.core.validation"].TOLERANCE_FLOOR
    for bad in (1e-300, floor / 10):
        with pytest.raises(ValueError, match=rf"^`chatter_tol` = {bad!r} is not allowed: must be at least {floor:g}"):
            idp.Tolerances(chatter_tol=bad)
    with pytest.raises(SystemExit) as info:
        main(["steady", "--chatter-tol", "1e-300", "--gap", "-28"])
    err = capsys.readouterr().err
    assert (
        info.value.code == 2
        and err.count("\n") == 1
        and err.split(": error: ")[1].startswith("argument --chatter-tol: `chatter_tol` = 1e-300 is not allowed")
    )
    message = sys.modules["impactdamper.core.validation"].work_bound_message
    tolerances = idp.Tolerances(chatter_tol=1e-12)
    assert message(REF_GAP_28, tolerances, "the work bound", 25).startswith("`chatter_tol` = 1e-12 is beyond")
    assert message(REF_GAP_28, tolerances, "the work bound", 3).startswith("`gap` = -28.0 is beyond")
    # At the floor both backends settle the same cycle (chatter, 1 T): nothing there at the last bit.
    at_floor = [
        idp.steady_state(REF_GAP_28, tolerances=idp.Tolerances(chatter_tol=floor), backend=b)
        for b in ("python", "compiled")
    ]
    assert [(s.regime, s.period_multiple) for s in at_floor] == [("chatter", 1)] * 2
    assert idp.steady_state(REF_GAP_28).regime == "chatter"


REF_GAP_28 = idp.Parameters(gap=-28.0)
SearchLimitError = sys.modules["impactdamper.core.events"].SearchLimitError


def test_closed_stdout_is_one_line():
    """``alg1 --json >&-`` ended in AttributeError: 'NoneType' object has no attribute 'write'."""
    proc = subprocess.run(
        [sys.executable, "-m", "impactdamper", "alg1", "--json"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        timeout=120,
        preexec_fn=lambda: __import__("os").close(1),
    )
    assert proc.returncode == 1
    assert proc.stderr == "impactdamper: error: cannot write the output: standard output is closed\n"


def test_building_the_parser_imports_no_solver():
    """Every command builds the whole parser first: it must not pay for scipy, numba or the
    design search (the design flags' defaults once imported the search, scipy.stats with it,
    and made `steady --json` 0.6 s slower)."""
    statement = "from impactdamper.cli.parser import build_parser; build_parser()"
    assert heavy_modules_after(statement, also=("impactdamper.studies.design.optimum",)) == []


@pytest.mark.parametrize(
    "band, option", [(("--theta-start", "1e-300"), "--theta-start"), (("--theta-stop", "1e300"), "--theta-stop")]
)
def test_a_band_end_beyond_the_range_names_its_own_flag(band, option, capsys):
    """`response --theta-start 1e-300` blamed --theta, a flag response refuses."""
    with pytest.raises(SystemExit) as info:
        main(["response", *band, "--points", "2"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1
    assert err.split(": error: ")[1].startswith(f"argument {option}: `theta` = {band[1]}".replace("1e300", "1e+300"))


@pytest.mark.parametrize(
    "flag, value, allowed",
    [
        ("--stiffness-drift", "0.5", "in [0, 0.3]"),
        ("--stiffness-drift", "-0.01", "in [0, 0.3]"),
        ("--damping-drift", "1", "in [0, 0.9]"),
        ("--damping-drift", "nan", "must be a finite number"),
    ],
)
def test_design_drift_flags_refuse_values_outside_their_ranges(flag, value, allowed, monkeypatch, capsys):
    """The absorber's drifts are refused before any search, in one line naming the flag and its range."""
    from impactdamper.studies.design import optimum

    monkeypatch.setattr(optimum, "design_optima", lambda *a, **k: pytest.fail("searched a refused input"))
    with pytest.raises(SystemExit) as info:
        main(["design", flag, value, "--quiet"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert f"argument {flag}: `{flag[2:].replace('-', '_')}` = " in err and allowed in err, err


@pytest.mark.parametrize(
    "argv, robust, stiffness, damping",
    [
        ([], None, 0.05, 0.2),
        (["--robust"], True, 0.05, 0.2),
        (["--stiffness-drift", "0.1", "--damping-drift", "0.4", "--robust"], True, 0.1, 0.4),
        (["--stiffness-drift", "0", "--damping-drift", "0"], None, 0.0, 0.0),
    ],
)
def test_design_flags_reach_the_search(argv, robust, stiffness, damping, monkeypatch, capsys):
    """--robust asks design_optima for the full robust table (robust=True; without it the
    criterion decides), and the drift flags set the Uncertainty it searches under."""
    from impactdamper.studies.design import optimum

    calls = []
    monkeypatch.setattr(optimum, "design_optima", lambda *a, **k: calls.append(k) or {"peak": 1.0})
    assert main(["design", *argv, "--json", "--quiet"]) == 0
    assert json.loads(capsys.readouterr().out) == {"peak": 1.0}
    (k,) = calls
    assert k["robust"] is robust
    assert (k["uncertainty"].stiffness, k["uncertainty"].damping) == (stiffness, damping)
    assert (k["uncertainty"].detuning, k["uncertainty"].restitution) == (0.1, 0.15)
