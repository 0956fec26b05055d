"""Periodic orbits solved directly (impactdamper.analysis.orbits, .shooting, .continuation):
shooting, admissibility, Floquet multipliers from saltation matrices, continuation, the cheap
steady state (impactdamper.steady_state(p, attractor=True)) and the CLI.

Every number is checked by an independent route: periodicity by the event-driven solver, the
multipliers by finite differences of the simulated stroboscopic map and by the growth of a
perturbation in simulation, grazing locations by closed forms (eq. 12's forced relative
amplitude; Algorithm No. 1's gap minimum), bifurcations by simulation on both sides.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.cli import main
from impactdamper.core.model import Model
from impactdamper.analysis.orbits import _stable_algorithm1_orbit
from impactdamper.analysis.shooting import Shooting
from impactdamper.analysis.strobe import stroboscopic_jacobian, _stroboscopic_map

REF = idp.Parameters()
# Relative state scale (x_st, x_st, x_st omega, x_st omega).
D = np.array([REF.x_st, REF.x_st, REF.x_st * REF.omega, REF.x_st * REF.omega])


def section(o, where: float = 0.5):
    """A section time inside the longest flight (the one ending at the cycle's first impact),
    one cycle later than the stored start, and the orbit's state there."""
    Tc = o.cycle_duration
    flight = o.times[0] + Tc - o.times[-1]
    t = o.times[0] - (1.0 - where) * flight + Tc
    y, _ = o.trajectory.sample(np.array(t))
    return float(t), y


@pytest.fixture(scope="module")
def single():
    """Algorithm No. 1's orbit at the reference case, Newton-confirmed."""
    return idp.solve_orbit(REF, "alg1")


@pytest.fixture(scope="module")
def steady10():
    return idp.steady_state(REF.replace(gap=-10.0), backend="python")


@pytest.fixture(scope="module")
def double(steady10):
    """The 3-impact 2T cycle at Delta0/x_st = -10 (the paper's Fig. 2b motion)."""
    return idp.solve_orbit(REF.replace(gap=-10.0), steady10)


# --- the direct solve --------------------------------------------------------------------
@pytest.mark.parametrize("which", ["single", "double"])
def test_periodicity_conditions_hold_to_1e12(which, request):
    o = request.getfixturevalue(which)
    k, z = o.period_multiple, o.impacts_per_cycle
    shoot = Shooting(o.p, k, z)
    F, _ = shoot.residual(shoot.pack(o.times, o.states_after), jacobian=False)
    assert np.max(np.abs(F)) <= 1e-12
    assert o.residual <= 1e-12
    model = Model(o.p)
    for before, after, imp in zip(o.states_before, o.states_after, o.impacts):
        assert abs(model.gap_of(before)) <= 1e-12 * o.p.x_st  # the impact is on the stop
        v = before[3] - before[2]
        assert v == pytest.approx(imp.velocity, rel=1e-14)
        assert after[3] - after[2] == pytest.approx(-o.p.R * v, rel=1e-12)  # eq. (22)
        assert o.p.m1 * after[2] + o.p.m2 * after[3] == pytest.approx(
            o.p.m1 * before[2] + o.p.m2 * before[3], rel=1e-13
        )
    # Independently: the event-driven solver, from a state on the cycle, returns to it after k T.
    t, y = section(o)
    back = _stroboscopic_map(o.p, t, y, k)
    assert np.max(np.abs((back - y) / D)) <= 1e-11


def test_newton_confirms_algorithm1_at_the_reference_case(single):
    a1 = idp.algorithm1(REF)
    assert single.seed == "alg1" and single.newton_iterations <= 2
    (imp,) = single.impacts
    assert imp.phase == pytest.approx(a1.impact_phase, abs=1e-12)
    assert imp.velocity == pytest.approx(a1.velocity, rel=1e-12)
    assert imp.impulse == pytest.approx(a1.S, rel=1e-12)
    assert (single.regime, single.period_multiple, single.impacts_per_cycle) == ("single_impact", 1, 1)


@pytest.mark.parametrize("gap", [-5.8, -10.0])
def test_newton_orbit_agrees_with_the_settled_cycle(gap, single, steady10):
    s = idp.steady_state(REF, backend="python") if gap == -5.8 else steady10
    o = idp.solve_orbit(s.p, s)
    assert (o.regime, o.period_multiple, o.impacts_per_cycle) == (s.regime, s.period_multiple, s.impacts_per_cycle)
    for a, b in zip(o.impacts, s.impacts):
        assert a.t_over_T == pytest.approx(b.t_over_T, abs=1e-9)
        assert a.phase == pytest.approx(b.phase, abs=1e-9)
        assert a.velocity / (s.p.x_st * s.p.omega) == pytest.approx(b.velocity / (s.p.x_st * s.p.omega), abs=1e-8)
    assert o.x1_max == pytest.approx(s.x1_max, abs=1e-8)
    assert o.cycle_start % s.p.T == pytest.approx(s.cycle_start % s.p.T, abs=1e-9 * s.p.T)
    assert o.periods == s.periods and o.seed == "simulate"


def test_regression_seed_at_large_absolute_time_converges(double):
    """Bug guarded: seeded from a settled cycle at t ~ 565 T, Newton stalled at a residual of
    3e-12 (sin(omega t) loses digits at large t); the cycle is now shifted to [0, T) first."""
    T = double.p.T
    o = idp.orbit_from_cycle(double.p, 2, double.times + 1000 * T, double.states_after)
    assert o.residual <= 1e-12
    assert np.max(np.abs(o.times - double.times)) <= 1e-12 * T


def test_relative_results_do_not_depend_on_the_free_scales(double):
    o = idp.solve_orbit(REF.replace(gap=-10.0, m1=37.5, x_st=0.01), "auto")
    assert [i.phase for i in o.impacts] == pytest.approx([i.phase for i in double.impacts], abs=1e-12)
    assert np.abs(o.multipliers) == pytest.approx(np.abs(double.multipliers), abs=1e-12)
    assert (o.x1_max, o.min_gap) == pytest.approx((double.x1_max, double.min_gap), abs=1e-11)


def test_repeated_cycle_has_squared_multipliers(single):
    o2 = idp.solve_orbit(REF, "alg1", period_multiple=2)
    assert (o2.period_multiple, o2.impacts_per_cycle, o2.regime) == (2, 2, "multi_impact")
    assert np.sort(np.abs(o2.multipliers)) == pytest.approx(np.sort(np.abs(single.multipliers) ** 2), rel=1e-9)


# --- admissibility ----------------------------------------------------------------------
def test_alg1_orbit_crossing_the_stop_is_rejected_with_the_reason():
    o = idp.solve_orbit(REF.replace(gap=-10.0), "alg1")
    a1 = idp.algorithm1(REF.replace(gap=-10.0))
    assert not o.admissible
    assert "gap negative on (0.2467, 0.6319) T after impact 1" in o.reason
    ((a, b),) = a1.negative_gap_intervals  # the same crossing by Algorithm No. 1's own scan
    assert (a, b) == pytest.approx((0.2467, 0.6319), abs=1e-4)
    assert o.min_gap == pytest.approx(a1.min_gap, abs=1e-9)
    assert o.to_dict()["admissible"] is False


def test_alg1_orbit_clear_of_the_stop_is_admissible(single):
    assert single.admissible and single.reason == ""
    assert single.min_velocity > 0
    # Dense check, independent of the certified search: the gap stays positive between impacts.
    t = np.linspace(single.times[0], single.times[0] + REF.T, 4001)[1:-1]
    x1, x2 = single.sample(t)
    assert np.min(x1 - x2) > 0.0


def test_orbit_with_a_negative_closing_velocity_is_not_admissible():
    """Past the grazing at U1 the one-impact equations still have a solution, with the impact
    hitting the stop from the wrong side: not a motion."""
    o = idp.solve_orbit(REF.replace(gap=11.0), "alg1")
    branch = idp.continue_orbit(o, "gap", (11.0, 11.5), stop_at_grazing=False, max_points=60)
    beyond = [q for q in branch.points if q.velocities[0] < 0]
    assert beyond and not any(q.admissible for q in beyond)
    q = beyond[0]
    bad = idp.orbit_from_cycle(REF.replace(gap=q.value), 1, q.times, q.states_after)
    assert not bad.admissible and "closing velocity" in bad.reason


# --- stability --------------------------------------------------------------------------
@pytest.mark.parametrize("which", ["single", "double"])
def test_multipliers_match_finite_differences_of_the_simulated_map(which, request):
    o = request.getfixturevalue(which)
    t, y = section(o, 0.4)
    M = o.monodromy(t)
    J = stroboscopic_jacobian(o.p, t, y, o.period_multiple)
    # Same section, same matrix: the saltation product against central differences (O(h^2)).
    assert np.max(np.abs(M - J)) <= 1e-6 * np.max(np.abs(M))
    fd = np.linalg.eigvals(J)
    for m in o.multipliers:
        assert np.min(np.abs(fd - m)) <= 1e-6
    # The multipliers do not depend on the section.
    t2, _ = section(o, 0.9)
    assert np.sort_complex(np.linalg.eigvals(o.monodromy(t2))) == pytest.approx(
        np.sort_complex(o.multipliers), abs=1e-10
    )


def test_reference_multipliers(single, double):
    assert single.stable and double.stable
    assert np.abs(single.multipliers) == pytest.approx([0.71128918, 0.71128918, 0.51199009, 0.51199009], abs=1e-8)
    assert np.abs(double.multipliers) == pytest.approx([0.92591183, 0.92591183, 0.36069277, 0.02787086], abs=1e-7)


def _deviation_growth(o, n: int, size: float) -> np.ndarray:
    """Simulate n periods from the orbit's section state displaced along its leading
    Floquet direction; the deviation (relative, max-norm) after each period."""
    p = o.p
    t, y0 = section(o)
    w, V = np.linalg.eig(o.monodromy(t))
    v = np.real(V[:, np.argmax(np.abs(w))])
    y = y0 + size * v / np.max(np.abs(v / D))
    devs = []
    for m in range(n):
        y = _stroboscopic_map(p, t + m * p.T, y, 1)
        devs.append((y - y0) / D)
    return np.array(devs)


def test_stable_and_unstable_orbits_are_told_apart_and_simulation_agrees(single):
    # Stable: the reference case; a perturbation decays like |mu|^n (complex pair: on average).
    devs = np.max(np.abs(_deviation_growth(single, 20, 1e-6)), axis=1)
    rate = (devs[-1] / devs[0]) ** (1 / 19)
    assert rate == pytest.approx(single.spectral_radius, rel=0.05)
    # Unstable: an admissible one-impact orbit past the period doubling (Delta0/x_st = 11.15).
    o = idp.solve_orbit(REF.replace(gap=11.15), "alg1")
    assert o.admissible and not o.stable
    mu = o.multipliers[0]
    assert abs(mu.imag) == 0.0 and mu.real == pytest.approx(-1.8617129, abs=1e-6)
    d = _deviation_growth(o, 12, 1e-10)
    j = int(np.argmax(np.abs(d[0])))
    ratios = d[1:, j] / d[:-1, j]
    assert ratios[-6:] == pytest.approx(np.full(6, mu.real), rel=1e-3)  # sign flips: period doubling


# --- closed-form regimes and cycles the direct solve does not handle -----------------------
def test_no_contact_and_stuck_cycles_in_closed_form():
    far = idp.solve_orbit(REF.replace(gap=15.0), "simulate")
    assert (far.regime, far.seed, far.admissible, far.stable) == ("no_contact", "closed_form", True, True)
    s = idp.steady_state(REF.replace(gap=15.0), backend="python")
    assert far.x1_max == pytest.approx(s.x1_max, abs=1e-9)
    model = Model(far.p)
    assert np.sort_complex(far.multipliers) == pytest.approx(
        np.sort_complex(np.linalg.eigvals(model.free.propagator(far.p.T))), abs=1e-12
    )
    # The gap's least value on the forced response: Delta0 - U1 (eq. 12's amplitude).
    assert far.min_gap == pytest.approx(15.0 - idp.algorithm1(far.p).U1 / far.p.x_st, abs=1e-12)
    stuck = idp.solve_orbit(REF.replace(gap=-40.0), "simulate")
    assert (stuck.regime, stuck.admissible, stuck.contact_fraction, len(stuck.multipliers)) == ("stuck", True, 1.0, 2)


def test_chatter_is_reported_not_solved():
    o = idp.solve_orbit(REF.replace(gap=-13.0), "simulate")
    assert o.regime == "chatter" and not o.solved and o.stable is None
    assert "persistent contact" in o.reason and len(o.multipliers) == 0
    d = o.to_dict()
    assert d["solved"] is False and d["multipliers"] == []


# --- continuation -----------------------------------------------------------------------
def test_single_impact_branch_grazes_the_stop_where_algorithm1_starts_to_cross_it(single):
    """Downward from the reference case the one-impact orbit stays stable and ends at an
    interior touch of the stop; its location matches the root of Algorithm No. 1's own gap
    minimum (an independent closed-form route)."""
    import scipy.optimize

    branch = idp.continue_orbit(single, "gap", (-12.0, -5.8), direction=-1)
    assert branch.end_reason == "grazing_interior"
    assert all(q.stable and q.admissible for q in branch.points)
    (graze,) = branch.special
    assert graze.kind == "grazing_interior" and "1/1" in graze.detail and "2/1" in graze.detail
    root = scipy.optimize.brentq(lambda g: idp.algorithm1(REF.replace(gap=g)).min_gap, -8.9, -8.8, xtol=1e-13)
    assert graze.value == pytest.approx(root, abs=1e-9)
    assert graze.value == pytest.approx(-8.848978948812, abs=1e-9)
    assert abs(graze.point.min_gap) <= 1e-12


def test_period_doubling_and_grazing_upward_match_closed_form_and_simulation():
    o = idp.solve_orbit(REF.replace(gap=11.0), "alg1")
    branch = idp.continue_orbit(o, "gap", (11.0, 12.0))
    kinds = [s.kind for s in branch.special]
    assert kinds == ["period_doubling", "grazing_velocity"] and branch.end_reason == "grazing_velocity"
    pd, graze = branch.special
    assert pd.value == pytest.approx(11.1067988149, abs=1e-8)
    assert np.min(np.abs(np.array(pd.point.multipliers) + 1.0)) <= 1e-6
    assert "loses stability" in pd.detail
    # The impact vanishes where the forced relative motion just reaches the stop: Delta0 = U1.
    assert graze.value == pytest.approx(idp.algorithm1(REF).U1 / REF.x_st, abs=1e-9)
    # Independent: the simulated map's Jacobian at the located gap has a multiplier at -1.
    q = pd.point
    at = idp.orbit_from_cycle(REF.replace(gap=pd.value), 1, q.times, q.states_after)
    t, y = section(at)
    assert np.min(np.abs(np.linalg.eigvals(stroboscopic_jacobian(at.p, t, y, 1)) + 1.0)) <= 1e-5
    # Simulation on the stable side settles on the continued orbit.
    below = idp.steady_state(REF.replace(gap=11.08), backend="python")
    on_branch = idp.solve_orbit(REF.replace(gap=11.08), "alg1")
    assert below.regime == "single_impact" and on_branch.stable
    assert below.impacts[0].phase == pytest.approx(on_branch.impacts[0].phase, abs=1e-8)


def test_fold_of_the_four_impact_cycle_matches_simulation_on_both_sides():
    """The 4-impact 3T cycle that simulation settles on at -8.8 turns back at a fold: on one
    side it exists and attracts, on the other there is no such cycle and the same start goes
    to the one-impact motion."""
    o = idp.solve_orbit(REF.replace(gap=-8.8), "simulate")
    assert (o.period_multiple, o.impacts_per_cycle, o.stable) == (3, 4, True)
    branch = idp.continue_orbit(o, "gap", (-8.8, -7.5))
    fold = next(s for s in branch.special if s.kind == "fold")
    assert fold.value == pytest.approx(-8.0990676, abs=1e-6)
    assert np.min(np.abs(np.array(fold.point.multipliers) - 1.0)) <= 1e-6
    near = branch.points[fold.index - 1]
    at_fold = idp.orbit_from_cycle(REF.replace(gap=fold.value), 3, fold.point.times, fold.point.states_after)
    for shift, regime, k, z in ((-0.01, "multi_impact", 3, 4), (+0.01, "single_impact", 1, 1)):
        p = REF.replace(gap=fold.value + shift)
        if shift < 0:
            cyc = idp.orbit_from_cycle(p, 3, near.times, near.states_after)
            assert cyc.admissible and cyc.stable
        else:
            with pytest.raises(idp.OrbitError):
                idp.orbit_from_cycle(p, 3, near.times, near.states_after)
        t, y = section(at_fold)
        y = y.copy()
        y[1] += shift * p.x_st  # same gap as at the fold
        s = idp.steady_state(p, t0=t, state=y, backend="python")
        assert (s.regime, s.period_multiple, s.impacts_per_cycle) == (regime, k, z)


def test_continuation_in_another_parameter_matches_direct_solves(single):
    branch = idp.continue_orbit(single, "R", (0.5, 0.8), direction=+1)
    assert branch.end_reason == "bound" and branch.end_value == 0.8
    assert branch.points[-1].value == 0.8
    direct = idp.solve_orbit(REF.replace(R=0.8), "alg1")
    assert branch.points[-1].phases[0] == pytest.approx(direct.impacts[0].phase, abs=1e-11)
    assert branch.points[-1].velocities[0] == pytest.approx(
        direct.impacts[0].velocity / (REF.x_st * REF.omega), rel=1e-11
    )
    mid = branch.points[len(branch.points) // 2]
    a1 = idp.algorithm1(REF.replace(R=mid.value))
    assert mid.phases[0] == pytest.approx(a1.impact_phase, abs=1e-11)
    d = branch.to_dict()
    assert d["parameter"] == "R" and len(d["points"]) == len(branch.points)
    json.dumps(d)


# --- the cheap steady state -------------------------------------------------------------
def test_attractor_uses_algorithm1_when_it_can(single):
    s = idp.steady_state(REF, backend="python")
    a = idp.steady_state(REF, attractor=True, backend="python")
    assert isinstance(a, idp.PeriodicOrbit) and a.periods == 0 and a.seed == "alg1"
    assert not isinstance(s, idp.PeriodicOrbit)  # steady_state itself is unchanged
    assert a.impacts[0].phase == pytest.approx(s.impacts[0].phase, abs=1e-9)
    assert a.x1_max == pytest.approx(s.x1_max, abs=1e-8)
    assert set(s.to_dict()) <= set(a.to_dict())


def test_attractor_falls_back_when_algorithm1_is_not_admissible(steady10):
    a = idp.steady_state(REF.replace(gap=-10.0), attractor=True, backend="python")
    assert not isinstance(a, idp.PeriodicOrbit)
    assert (a.regime, a.period_multiple, a.impacts_per_cycle) == ("multi_impact", 2, 3)
    assert a.impacts[0].phase == steady10.impacts[0].phase


def test_stable_algorithm1_orbit_is_the_attractor_or_none(single):
    # At the reference case Algorithm No. 1's orbit is admissible and stable: the same cycle as
    # the direct solve from it (one Newton-confirmed impact, same phase and multipliers).
    o = _stable_algorithm1_orbit(idp.algorithm1(REF))
    assert o is not None and o.seed == "alg1"
    assert o.impacts[0].phase == single.impacts[0].phase
    assert np.array_equal(o.multipliers, single.multipliers)
    # At Delta0/x_st = -10 the orbit crosses the stop between impacts (Fig. 2a): no attractor.
    assert not idp.algorithm1(REF.replace(gap=-10.0)).admissible
    assert _stable_algorithm1_orbit(idp.algorithm1(REF.replace(gap=-10.0))) is None
    assert _stable_algorithm1_orbit(None) is None  # Algorithm No. 1 failed: nothing to confirm


# --- command line and bad input -----------------------------------------------------------
def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "impactdamper", *args], capture_output=True, text=True, timeout=120)


@pytest.mark.slow
def test_cli_orbit_json_has_the_steady_keys_plus_the_checks(double, steady10, capsys):
    proc = run("orbit", "--gap", "-10", "--json")
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    d = json.loads(proc.stdout)
    assert set(steady10.to_dict()) <= set(d)  # the keys of `steady --json`
    assert (d["regime"], d["period_multiple"], d["impacts_per_cycle"]) == ("multi_impact", 2, 3)
    assert d["admissible"] is True and d["stable"] is True and d["solved"] is True
    assert d["multipliers"] == sorted(d["multipliers"], reverse=True)
    assert d["multipliers"] == pytest.approx(np.abs(double.multipliers), abs=1e-10)
    assert [i["phase"] for i in d["impacts"]] == pytest.approx([i.phase for i in double.impacts], abs=1e-12)
    assert main(["orbit", "--gap", "-10", "--seed", "alg1", "--json"]) == 0
    alg = json.loads(capsys.readouterr().out)
    assert alg["admissible"] is False and "gap negative" in alg["reason"] and alg["periods_simulated"] == 0


@pytest.mark.parametrize(
    "args, flag",
    [
        (("--seed", "foo"), "--seed"),
        (("--period-multiple", "0"), "--period-multiple"),
        (("--gap", "-10", "--seed", "simulate", "--period-multiple", "3"), "--period-multiple"),
        (("--R", "1.5"), "--R"),
    ],
)
def test_cli_orbit_bad_input_is_one_line_exit_2(args, flag, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["orbit", *args])
    assert exit_info.value.code == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and flag in err


def test_api_bad_input_names_the_argument(single):
    with pytest.raises(ValueError, match="`seed`"):
        idp.solve_orbit(REF, "guess")
    with pytest.raises(ValueError, match="`period_multiple`"):
        idp.orbit_from_cycle(REF, 0, single.times, single.states_after)
    with pytest.raises(ValueError, match="`parameter`"):
        idp.continue_orbit(single, "Delta0", (-6.0, -5.0))
    with pytest.raises(ValueError, match="`bounds`"):
        idp.continue_orbit(single, "gap", (-5.0, -4.0))
    with pytest.raises(ValueError, match="`orbit`"):
        idp.continue_orbit(idp.steady_state(REF, backend="python"), "gap", (-6.0, -5.0))
    with pytest.raises(idp.OrbitError, match="no orbit"):
        idp.solve_orbit(REF.replace(gap=-40.0), "alg1")
