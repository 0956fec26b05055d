"""Choosing a suppressor (impactdamper.studies.design.design): the linear baselines against the
library's own flow and closed forms, Den Hartog's optimum as the optimiser's check, and the
design chart's bookkeeping.

* The relative closed form of the two-mass system against eq. (10) solved as a matrix
  (core.linear.forced_amplitudes), and against the event-driven flow with a gap the motion
  never reaches, for the absorber without a stop and for the optimal TMD.
* The bare object against the event-driven flow with a vanishing suppressor (mu = 1e-9: the
  object feels it to O(mu)).
* Den Hartog: for an undamped object the optimiser's (studies.design.optimum.optimal_tmd) peak lies between the fixed points' height
  sqrt(1 + 2/mu) (a lower bound for every TMD) and the peak at Den Hartog's own tuning and
  damping, with his tuning 1/(1 + mu) and its two resonance peaks equal (the minimax optimum).
* The optimum with the object's damping is a local minimum (no nearby design is better).
* The chart picks the gap with the smallest criterion; the good band is the contiguous run
  within the tolerance.
* The design stage's config: its parameters override the reference case's, the gap grids, the
  response's gaps (the best first, each once), the runs of a flag over theta.
"""

import numpy as np
import pytest

from impactdamper.analysis.linear_device import LinearDevice, den_hartog
from impactdamper.analysis.response import frequency_response
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.parameters import Parameters
from impactdamper.studies.design.devices import TmdCriterion, Uncertainty
from impactdamper.studies.design.optimum import optimal_tmd
from impactdamper.studies.design.design import (
    design_band,
    design_chart_2d,
    design_gaps,
    design_parameters,
    gap_chart,
    _good_band,
    response_gaps,
    _runs_where,
)

NO_CONTACT_GAP = 1.0e3
# The settled cycle is the periodic one to the sweep's settle tolerance 1e-9 (in x_st): ten times.
FLOW_ATOL = 1e-8
BAND = (0.5, 1.5)


def tmd(mu: float, delta1: float, band: tuple, criterion: str = "peak") -> tuple:
    """The optimal TMD (the one optimiser): its device and its criterion's value."""
    r = optimal_tmd(TmdCriterion(mu, delta1, band, criterion, Uncertainty()))
    return LinearDevice(mu, r.x["N"], delta1, r.x["delta2"]), r.value


@pytest.mark.parametrize(
    "mu, N, delta1, delta2, theta",
    [
        (0.08, 0.5, 0.05, 0.05, 0.9),
        (0.2, 1.1, 0.0, 0.3, 1.05),
        (0.01, 0.95, 0.1, 0.02, 0.97),
    ],
)
def test_relative_closed_form_is_eq_10(mu, N, delta1, delta2, theta):
    p = Parameters(mu=mu, N=N, delta1=delta1, delta2=delta2, theta=theta)
    x1, _ = forced_amplitudes(p)
    assert abs(LinearDevice(mu, N, delta1, delta2).amplitude([theta])[0] - abs(x1) / p.x_st) <= 1e-12 * abs(x1)
    bare = 1.0 / abs(1.0 - theta**2 + 2j * delta1 * theta)
    assert LinearDevice.bare(delta1).amplitude([theta])[0] == pytest.approx(bare, rel=1e-14)


def test_absorber_and_tmd_against_the_no_contact_flow():
    optimal, _ = tmd(0.08, 0.05, BAND)
    for device in (LinearDevice(0.08, 0.5, 0.05, 0.05), optimal):
        p = Parameters(gap=NO_CONTACT_GAP, N=device.N, delta2=device.delta2)
        r = frequency_response(p, 0.7, 1.3, 7, locate=False)
        expected = device.amplitude(r.thetas)
        assert all(q.up.regime == "no_contact" for q in r.points)
        assert np.max(np.abs(r.worst_x1() - expected)) <= FLOW_ATOL


def test_bare_object_against_the_flow_with_a_vanishing_suppressor():
    mu = 1e-9
    p = Parameters(gap=NO_CONTACT_GAP, mu=mu, N=3.0)
    r = frequency_response(p, 0.7, 1.3, 5, locate=False)
    bare = LinearDevice.bare(p.delta1).amplitude(r.thetas)
    # The suppressor changes |x1| by O(mu |x1|^2 N^2 ...) ~ 1e-6 at most here; the flow adds 1e-8.
    assert np.max(np.abs(r.worst_x1() - bare) / bare) <= 1e-6


@pytest.mark.parametrize("mu", [0.02, 0.08, 0.2])
def test_optimiser_against_den_hartog(mu):
    dh = den_hartog(mu)
    band = (0.4, 1.6)
    optimal, peak = tmd(mu, 0.0, band)
    at_dh = LinearDevice(mu, dh["N"], 0.0, dh["delta2"]).peak(band)[1]
    # Every TMD passes through the fixed points: the peak is at least their height.
    assert peak >= dh["peak"] * (1 - 1e-9)
    assert peak <= at_dh
    # Den Hartog's equal-height tuning is the optimum's (to the optimiser's tolerance) ...
    assert abs(optimal.N - dh["N"]) <= 1e-3 * dh["N"]
    # ... and the optimum's peak exceeds the bound by well under 1 % (fixed-point theory's error).
    assert peak <= 1.005 * dh["peak"]
    # Den Hartog's damping only approximates the minimax one (it levels the fixed points' slopes);
    # the minimax optimum instead makes the two resonance peaks equal: to 1e-3 relative here.
    th = np.linspace(*band, 200001)
    y = optimal.amplitude(th)
    peaks = np.sort(y[1:-1][(y[1:-1] > y[:-2]) & (y[1:-1] > y[2:])])
    assert len(peaks) == 2 and peaks[1] - peaks[0] <= 1e-3 * peaks[1], peaks


def test_damped_optimum_is_a_local_minimum():
    optimal, peak = tmd(0.08, 0.05, BAND)
    for dN, dd in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1)):
        N, d2 = optimal.N * (1 + 0.01 * dN), optimal.delta2 * (1 + 0.01 * dd)
        assert LinearDevice(0.08, N, 0.05, d2).peak(BAND)[1] >= peak * (1 - 1e-9)
    average, _ = tmd(0.08, 0.05, BAND, "band_average")
    grid = np.linspace(*BAND, 51)
    assert average.band_average(grid) <= optimal.band_average(grid) and peak <= average.peak(BAND)[1]


def test_good_band_is_the_contiguous_run_within_the_tolerance():
    gaps = [0, 1, 2, 3, 4, 5, 6]
    values = [5.0, 3.25, 3.1, 3.0, 3.2, 3.4, 3.05]
    assert _good_band(gaps, values, 0.1) == (1.0, 4.0)  # 3.05 at 6 is within, but past 3.4 at 5
    assert _good_band(gaps, values, 0.0) == (3.0, 3.0)
    assert _good_band(gaps, values, 0.2) == (1.0, 6.0)
    with pytest.raises(ValueError, match="^`tolerance` = "):
        _good_band(gaps, values, -0.1)


def test_gap_chart_picks_the_smallest_criterion():
    chart = gap_chart(Parameters(), [-5.8, 0.85, 3.0], BAND, 0.05)
    for name in ("peak", "band_average"):
        values = chart.criterion(name)
        best = chart.best(name)
        assert best["value"] == values.min() and best["gap"] == chart.gaps[int(np.argmin(values))]
        assert best["good_from"] <= best["gap"] <= best["good_to"]
    # The criterion is the worst branch's (never below a grid sample of either direction).
    w = chart.branches[1]
    assert chart.criterion("peak")[1] == w.peak >= np.nanmax(np.fmax(w.up, w.down))
    pulse, impacts = chart.loads()
    assert impacts[1] == np.nanmax(np.r_[w.up_impacts, w.down_impacts])
    assert pulse[1] > 0 and len(chart.rows()) == 3
    # At one theta of the grid: the worst motion there, per gap.
    at = chart.at_theta(1.0)
    i = int(np.argmin(np.abs(w.thetas - 1.0)))
    assert at[1] == w.worst_sample[i] >= max(w.up[i], w.down[i])
    assert [row["max_abs_x1_at_theta"] for row in chart.rows(1.0)] == list(at)
    with pytest.raises(ValueError, match="^`theta` = 1.12 is not allowed: must be on the chart's theta grid"):
        chart.at_theta(1.12)


def test_design_config_overrides_the_reference_case():
    reference = Parameters(gap=-5.8, theta=1.1).to_dict()
    design = {
        "mu": 0.1,
        "N": 0.6,
        "R": 0.5,
        "theta_start": 0.6,
        "theta_stop": 1.4,
        "gap_start": -8.0,
        "gap_stop": 5.0,
        "gap_points": 53,
        "second_gap_points": 14,
    }
    p = design_parameters(reference, design)
    assert (p.mu, p.N, p.R) == (0.1, 0.6, 0.5)
    assert (p.delta1, p.delta2, p.gap, p.theta) == (reference["delta1"], reference["delta2"], -5.8, 1.1)
    assert design_band(design) == (0.6, 1.4)
    assert np.diff(design_gaps(design)) == pytest.approx(0.25, rel=1e-12)
    assert design_gaps(design, second=True)[[0, -1]].tolist() == [-8.0, 5.0]
    assert np.diff(design_gaps(design, second=True)) == pytest.approx(1.0, rel=1e-12)


def test_response_gaps_put_the_best_first_and_each_once():
    assert response_gaps(0.85, [-5.8, 0.85]) == [0.85, -5.8]
    assert response_gaps(-2.0, [-5.8, 0.85, -5.8]) == [-2.0, -5.8, 0.85]


def test_runs_where_a_flag_holds():
    thetas = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
    assert _runs_where(thetas, [True, True, False, True, False, True]) == [(0.5, 0.6), (0.8, 0.8), (1.0, 1.0)]
    assert _runs_where(thetas, [False] * 6) == []
    assert _runs_where(thetas, np.ones(6, dtype=bool)) == [(0.5, 1.0)]


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: design_chart_2d(Parameters(), "gap", [1.0], [0.0]), "name"),
        (lambda: gap_chart(Parameters(), [], BAND, 0.05), "gaps"),
        (lambda: gap_chart(Parameters(), [0.0], BAND, 0.0), "step"),
    ],
)
def test_bad_input_is_one_line_naming_the_argument(call, name):
    with pytest.raises(ValueError) as err:
        call()
    assert str(err.value).startswith(f"`{name}` = ") and "\n" not in str(err.value)
