"""Frequency response (impactdamper.analysis.response): the upward and downward theta sweeps'
cycles against closed forms.

* Without contact (a gap far beyond the motion) the library's event-driven flow is the linear
  forced response of eq. (10): max|x1| and max|x2| against |x1p_hat|, |x2p_hat| and against the
  relative closed form of studies.design, and the dampers' dissipation per period against
  pi omega (k1 |x1p_hat|^2 + k2 |x2p_hat - x1p_hat|^2).
* Energy balance of settled impacting cycles: input = impacts + dampers (+ drift), each term
  computed on its own.
* Pulse per impact: m2 times the jump of the suppressor's velocity, and the steady state's own.
* Hysteresis: a band where the upward sweep keeps impacting while the downward one stays without
  contact (gap 3, theta 1.2-1.45) is flagged, a gap without contact is not.
* Bad input: one-line errors naming the argument, from the API and the command line (exit 2).
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from impactdamper.analysis.band_sweeps import GRID_RTOL, band_grid, band_points, band_sweeps
from impactdamper.analysis.cycle_metrics import _energy_balance, cycle_metrics
from impactdamper.analysis.response import (
    HYSTERESIS_TOL,
    frequency_response,
    _theta_grid,
)
from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.peak_location import ZOOM_POINTS
from impactdamper.analysis.peaks import STEP
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.sweeps import with_value
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import EventDrivenSolver
from impactdamper.core.steady import steady_state
from impactdamper.analysis.linear_device import LinearDevice

# A gap the motion never reaches: 1000 x_st against forced amplitudes below 30 x_st.
NO_CONTACT_GAP = 1.0e3
# The settled cycle is the periodic one to the sweep's settle tolerance (1e-9 x_st, x_st omega at
# the section: the free response left over); the flow itself is exact to rounding. Ten times that.
AMPLITUDE_ATOL = 10 * SweepSettings().settle_tol
# Energies per period over c1 x_st^2 carry the same leftover, relative to amplitudes ~1: 1e-7.
ENERGY_RTOL = 1e-7
# Gauss-Legendre on smooth pieces: the balance closes to rounding (~1e-13); 1e-10 leaves margin.
BALANCE_TOL = 1e-10


@pytest.mark.parametrize("delta1, delta2, N", [(0.05, 0.05, 0.5), (0.0, 0.1, 0.9), (0.2, 0.01, 1.3)])
def test_no_contact_flow_is_the_linear_forced_response(delta1, delta2, N):
    p = Parameters(gap=NO_CONTACT_GAP, delta1=delta1, delta2=delta2, N=N)
    r = frequency_response(p, 0.6, 1.4, 9, locate=False)
    device = LinearDevice.of(p)
    for q, c, c2 in zip(r.points, device.amplitude(r.thetas), device.absorber(r.thetas)):
        a1, a2 = (abs(x) / p.x_st for x in forced_amplitudes(with_value(p, "theta", q.theta)))
        assert q.linear_x1 == c and q.linear_x2 == c2  # the response's linear columns
        assert abs(a2 - c2) <= 1e-12 * c2
        for m in (q.up, q.down):
            assert m.regime == "no_contact"
            assert abs(m.max_abs_x1 - a1) <= AMPLITUDE_ATOL, (q.theta, m.max_abs_x1, a1)
            assert abs(m.max_abs_x2 - a2) <= AMPLITUDE_ATOL, (q.theta, m.max_abs_x2, a2)
            assert m.impacts_per_period == 0 and m.peak_impulse == 0 and m.energy_impacts == 0
        assert abs(a1 - c) <= 1e-12 * c  # eq. (10) solved as a matrix against the relative closed form
        assert not q.hysteresis
        # Dissipation per period of the forced response: pi omega (k1 |X1|^2 + k2 |X2 - X1|^2).
        pq = with_value(p, "theta", q.theta)
        X1, X2 = forced_amplitudes(pq)
        expected = math.pi * pq.omega * (pq.k1 * abs(X1) ** 2 + pq.k2 * abs(X2 - X1) ** 2) / (pq.c1 * pq.x_st**2)
        assert abs(q.up.energy_dampers - expected) <= ENERGY_RTOL * expected
        assert abs(q.up.energy_input - expected) <= ENERGY_RTOL * expected


@pytest.mark.parametrize("gap", [0.85, -5.8, 3.0])
def test_energy_balance_of_settled_cycles(gap):
    r = frequency_response(Parameters(gap=gap), 0.8, 1.2, 5, locate=False)
    for q in r.points:
        for m in (q.up, q.down):
            assert m.balance <= BALANCE_TOL, (gap, q.theta, m)
            if m.regime != "nonperiodic":
                # Settled: input equals the two losses, up to the settle tolerance's drift.
                assert abs(m.energy_input - m.energy_impacts - m.energy_dampers) <= 1e-7 * m.energy_input
                assert m.energy_impacts >= 0 and m.energy_dampers > 0


def test_energy_balance_over_any_window_closes_with_the_drift():
    # A transient (not settled) from Algorithm No. 2's step 1: the mechanical energy changes,
    # and input - losses must equal that change.
    p = Parameters(gap=-2.0)
    solver = EventDrivenSolver(p)
    solver.advance(3.3 * p.T)
    e = _energy_balance(solver.trajectory, 0.1 * p.T, 3.2 * p.T)
    assert len([x for x in solver.trajectory.events if x.kind == "impact"]) >= 2
    assert abs(e["drift"]) > 1e-3 * p.c1 * p.x_st**2
    assert abs(e["input"] - e["impacts"] - e["dampers"] - e["drift"]) <= BALANCE_TOL * abs(e["input"])


def test_pulse_is_m2_times_the_suppressors_velocity_jump():
    p = Parameters(gap=0.85)
    solver = EventDrivenSolver(p)
    solver.advance(5 * p.T)
    impacts = solver.trajectory.impacts()
    assert impacts
    for e in impacts:
        assert abs(e.impulse - p.m2 * (e.before[3] - e.after[3])) <= 1e-12 * e.impulse
        assert abs(e.impulse - p.m1 * (e.after[2] - e.before[2])) <= 1e-12 * e.impulse
    # The response's pulse equals the steady state's (its own settled run), over m1 x_st omega.
    s = steady_state(p)
    assert s.regime == "single_impact"
    m = cycle_metrics(solve_point(p))
    expected = s.impacts[0].impulse / (p.m1 * p.x_st * p.omega)
    assert m.impacts_per_period == 1
    assert abs(m.peak_impulse - expected) <= 1e-6 * expected
    assert m.mean_impulse == m.peak_impulse
    assert abs(m.max_abs_x1 - s.x1_max) <= 1e-7 * s.x1_max


def test_hysteresis_where_the_two_sweeps_settle_on_different_motions():
    r = frequency_response(Parameters(gap=3.0), 1.1, 1.8, 15, locate=False)
    flagged = [q for q in r.points if q.hysteresis]
    assert flagged, [(q.theta, q.up.label, q.down.label) for q in r.points]
    for q in flagged:
        assert q.up.label != q.down.label or abs(q.up.max_abs_x1 - q.down.max_abs_x1) > HYSTERESIS_TOL * q.worst_x1
    # The upward sweep keeps the impacts (1/2) to theta 1.45, the downward one stays without
    # contact from 1.8 down to 1.2 (the sweeps of step <= 0.02 that the worst branch is located on).
    assert any(q.up.impacts_per_period > 0 and q.down.regime == "no_contact" for q in flagged)
    assert not r.points[0].hysteresis and not r.points[-1].hysteresis
    for q in r.points:
        if not q.hysteresis:
            assert q.up.label == q.down.label
            assert abs(q.up.max_abs_x1 - q.down.max_abs_x1) <= HYSTERESIS_TOL * q.worst_x1
    assert r.to_dict()["hysteresis_points"] == len(flagged)


def test_compiled_loop_gives_the_reference_motions():
    """Sweeps whose simulations run their period loop compiled (the default) against the
    pure-Python ones: the same motion at every theta both ways, and x1_max of the same cycle."""
    a = frequency_response(Parameters(gap=3.0), 0.8, 1.3, 11, locate=False)
    b = frequency_response(Parameters(gap=3.0), 0.8, 1.3, 11, settings=SweepSettings(backend="python"), locate=False)
    for qa, qb in zip(a.points, b.points):
        for ma, mb in ((qa.up, qb.up), (qa.down, qb.down)):
            assert ma.label == mb.label, (qa.theta, ma.label, mb.label)
            if ma.regime != "nonperiodic":
                assert abs(ma.max_abs_x1 - mb.max_abs_x1) <= 1e-9 * max(1.0, mb.max_abs_x1)


def _batch_calls(monkeypatch) -> list:
    """Record every batch call (its values and chain length) of the library from here on."""
    import impactdamper.analysis.batch as batch

    calls, real = [], batch.steady_states

    def counted(base, names, values, **kw):
        calls.append((np.array(values, float), kw.get("chain_length"), kw.get("chain", True)))
        return real(base, names, values, **kw)

    monkeypatch.setattr(batch, "steady_states", counted)
    return calls


def test_the_response_sweeps_each_direction_once(monkeypatch):
    """One batch call sweeps the band both ways (its chains of the whole grid, each response theta
    in it once per direction); the worst branch is located on those sweeps (its other calls are
    the brackets' short continuations and the random starts), the ladder is not run."""
    import impactdamper.analysis.sweeps as sweeps

    monkeypatch.setattr(sweeps, "solve_point", None)  # (the ladder's two_way_sweep would call it)
    calls = _batch_calls(monkeypatch)
    thetas = np.linspace(0.9, 1.1, 9)
    r = frequency_response(Parameters(gap=0.85), 0.9, 1.1, 9)
    grid = r.located.thetas
    whole = [(v, n) for v, n, chain in calls if chain and n == len(grid)]
    assert len(whole) == 1 and len(whole[0][0]) == 2 * len(grid), [(len(v), n, c) for v, n, c in calls]
    for t in thetas:
        assert np.sum(whole[0][0][:, 0] == t) == 2, t
    others = [n for v, n, chain in calls if not (chain and n == len(grid))]
    assert others and set(others) <= {None, ZOOM_POINTS}  # (the location's: brackets, random starts)


def test_the_table_is_the_located_sweeps_rows():
    """Each row is the cycle of the located search's own sweep point at that theta: the grid holds
    the response's thetas (and the locator's steps), the rows equal the batch rows' metrics, and
    the table does not depend on ``locate``."""
    p, thetas = Parameters(gap=0.85), np.linspace(0.9, 1.1, 9)
    r = frequency_response(p, 0.9, 1.1, 9)
    grid = r.located.thetas
    assert set(thetas.tolist()) <= set(grid.tolist())
    assert np.all(
        np.min(np.abs(np.linspace(0.9, 1.1, band_points([(0.9, 1.1)], STEP))[:, None] - grid), axis=1) <= GRID_RTOL
    )
    s = band_sweeps([p], [(0.9, 1.1)], step=STEP, thetas=[thetas], settings=SweepSettings())
    points = s.points(0, thetas)
    for i, q in enumerate(r.points):
        j = int(np.flatnonzero(grid == q.theta)[0])
        assert q.up == cycle_metrics(points["up"][i]) and q.down == cycle_metrics(points["down"][i])
        assert (points["up"][i].x1_max, points["down"][i].x1_max) == (r.located.up[j], r.located.down[j])
    assert frequency_response(p, 0.9, 1.1, 9, locate=False).rows() == r.rows()


def test_on_point_is_called_once_per_row():
    ticks = []
    r = frequency_response(Parameters(gap=0.85), 0.9, 1.1, 5, on_point=lambda: ticks.append(1), locate=False)
    assert len(ticks) == 2 * len(r.points) == 10


def test_band_grid_holds_the_thetas_given():
    band = (0.5, 1.5)
    given = np.linspace(0.5, 1.5, 61)
    grid = band_grid(band, 0.02, given)
    assert set(given.tolist()) <= set(grid.tolist()) and np.all(np.diff(grid) > 0)
    # 51 steps and 61 thetas, 11 in common (0.5, 0.6, ..., 1.5: one ulp apart, the given kept)
    assert len(grid) == 101
    assert np.array_equal(band_grid(band, 0.02), np.linspace(0.5, 1.5, 51))
    with pytest.raises(ValueError, match="^`thetas` = "):
        band_grid(band, 0.02, [1.6])


def test_deterministic():
    a = frequency_response(Parameters(gap=0.85), 0.9, 1.1, 3).to_dict()
    b = frequency_response(Parameters(gap=0.85), 0.9, 1.1, 3).to_dict()
    assert json.dumps(a) == json.dumps(b)


@pytest.mark.parametrize(
    "args, name",
    [
        ((0.0, 1.0, 3), "theta_start"),
        ((1.0, 0.5, 3), "theta_stop"),
        ((0.5, 1.5, 0), "points"),
        ((0.5, 1.5, 2.5), "points"),
        ((0.5, float("nan"), 3), "theta_stop"),
        (("a", 1.5, 3), "theta_start"),
        ((0.5, 1.5, True), "points"),
        ((0.5, 0.6, 1), "theta_stop"),
    ],
)
def test_bad_grid_is_one_line_naming_the_argument(args, name):
    with pytest.raises(ValueError) as err:
        _theta_grid(*args)
    assert str(err.value).startswith(f"`{name}` = ")
    assert "is not allowed" in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(ValueError, match=f"^`{name}` = "):
        frequency_response(Parameters(), *args)


def test_bad_arguments_of_frequency_response():
    with pytest.raises(TypeError, match="^`p` = "):
        frequency_response({"gap": 1.0})
    with pytest.raises(ValueError, match="^`hysteresis_tol` = "):
        frequency_response(Parameters(), hysteresis_tol=0.0)
    with pytest.raises(TypeError, match="^`settings` = "):
        frequency_response(Parameters(), settings={"settle_tol": 1e-9})


def _cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "impactdamper", "response", *args], capture_output=True, text=True, timeout=120
    )


@pytest.mark.slow
def test_cli_response_json_keys_and_values():
    proc = _cli("--gap", "0.85", "--theta-start", "0.9", "--theta-stop", "1.1", "--points", "3", "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    api = frequency_response(Parameters(gap=0.85), 0.9, 1.1, 3)
    assert d["peak_max_abs_x1"] == pytest.approx(api.peak(), rel=1e-12)
    assert [q["theta"] for q in d["points"]] == pytest.approx([0.9, 1.0, 1.1])
    for key in (
        "max_abs_x1",
        "max_abs_x2",
        "impacts_per_period",
        "mean_impulse",
        "peak_impulse",
        "energy_impacts",
        "energy_dampers",
        "energy_input",
        "regime",
    ):
        assert key in d["points"][0]["up"] and key in d["points"][0]["down"]
    assert "hysteresis" in d["points"][0] and "linear_max_abs_x1" in d["points"][0]


@pytest.mark.slow
@pytest.mark.parametrize(
    "args, flag",
    [
        (("--points", "0"), "--points"),
        (("--theta-start", "-1"), "--theta-start"),
        (("--theta-start", "1.2", "--theta-stop", "1.1"), "--theta-stop"),
        (("--points", "x"), "--points"),
        (("--settle-tol", "2"), "--settle-tol"),
        (("--gap", "nan"), "--gap"),
    ],
)
def test_cli_bad_input_exits_2_with_one_line(args, flag):
    proc = _cli(*args)
    assert proc.returncode == 2
    assert proc.stdout == ""
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and f"argument {flag}" in lines[0], proc.stderr


@pytest.mark.slow
def test_far_above_resonance_the_peak_is_a_settled_motion():
    """``response --theta-start 100 --theta-stop 200 --points 3`` reported 75.8 x_st at theta 200,
    a random start's unsettled end (the free motion decays by 0.9984 a period there), where every
    settled motion is 3e-5 to 1.2e-4 x_st. The peak is now the settled motions' (below 1e-3,
    within 1e-6 relative of the largest settled grid sample, a stuck 1/1 motion), and each
    unsettled sample is counted beside it with the periods it ran."""
    proc = _cli("--theta-start", "100", "--theta-stop", "200", "--points", "3", "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    settled = [m["max_abs_x1"] for q in d["points"] for m in (q["up"], q["down"]) if m["regime"] != "nonperiodic"]
    assert d["peak_max_abs_x1"] < 1e-3
    assert d["peak_max_abs_x1"] == pytest.approx(max(settled), rel=1e-6)
    assert d["unsettled_points"] == len(d["unsettled"]) >= 1
    assert all(u["periods"] >= 2 and u["source"] in ("up", "down", "random") for u in d["unsettled"])
    assert max(u["max_abs_x1"] for u in d["unsettled"]) > 10 * d["peak_max_abs_x1"]  # (what used to be the peak)
