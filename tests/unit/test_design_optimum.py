"""Choosing a suppressor, answered (impactdamper.studies.design.design's located peaks and closed-form
linear peaks; impactdamper.studies.design.optimum's optimiser, detuning, stroke and loads; the
``design`` command).

* The linear devices' peaks and strokes in closed form against a dense grid (200001 points):
  never below the grid's largest value, above it by at most the grid's own error.
* The impact suppressor's located peak against a dense local scan (continuation through 400
  points across the grid bracket of the peak): the same value to the located peak's stated
  tolerance AMPLITUDE_RTOL and the same theta to the scan's step; a peak at a jump (the end of
  a periodic branch) likewise, to 3e-4 (a scan step's reach on a square-root fold).
* The TMD optimum of an undamped object against Den Hartog's tuning and damping.
* The optimiser against a brute-force grid on a small box.
* Detuning maps the relative parameters as the physics says: a TMD on a detuned object
  computed two ways.
* The command: its JSON keys, its one-line errors.
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from impactdamper.analysis.point import SweepSettings
from impactdamper.core.parameters import Parameters
from impactdamper.studies.design import design as dz
from impactdamper.studies.design.design import (
    AMPLITUDE_RTOL,
    THETA_TOL,
    LinearDevice,
    band_grid,
    den_hartog,
    impact_band_response,
    linear_maxima,
)
from impactdamper.studies.design.optimum import Budget, detuned, minimise, optimise_tmd, sensitivity, worst_case_tmd

BAND = (0.5, 1.5)
DENSE = 200001


@pytest.mark.parametrize(
    "mu, N, delta1, delta2",
    [
        (0.0, 0.5, 0.05, 0.05),
        (0.08, 0.5, 0.05, 0.05),
        (0.08, 0.9059, 0.05, 0.158),
        (0.2, 0.83, 0.0, 0.21),
        (0.01, 1.2, 0.1, 0.01),
    ],
)
def test_linear_peak_and_stroke_against_a_dense_grid(mu, N, delta1, delta2):
    d = LinearDevice(mu, N, delta1, delta2)
    th = np.linspace(*BAND, DENSE)
    for located, values in ((d.peak(BAND), d.amplitude(th)), (d.stroke_peak(BAND), d.stroke(th))):
        i = int(np.argmax(values))
        # Never below the grid, above it at most by the grid's error: a parabola's top between
        # two samples 5e-6 apart on a peak of half-width >= 0.005 lies within 1e-6 relative.
        assert located[1] >= values[i] * (1 - 1e-12)
        assert located[1] <= values[i] * (1 + 1e-6)
        assert abs(located[0] - th[i]) <= 1e-5 or values[i] == 0.0


def test_linear_maxima_finds_both_resonances_of_a_tmd():
    d = LinearDevice(0.08, 0.9059, 0.05, 0.158)
    num, den, _ = d._polys()
    maxima = linear_maxima(num, den, BAND)
    interior = [m for m in maxima if BAND[0] < m[0] < BAND[1]]
    th = np.linspace(*BAND, DENSE)
    y = d.amplitude(th)
    grid = th[1:-1][(y[1:-1] > y[:-2]) & (y[1:-1] > y[2:])]
    assert len(interior) == len(grid) == 2
    assert np.max(np.abs(np.sort([m[0] for m in interior]) - np.sort(grid))) <= 1e-5


def _dense_scan(p, peak, r, points=401):
    """Continuation through ``points`` thetas across the grid bracket of ``peak`` in its
    direction, from the grid point before the bracket; returns (theta, value) of the largest."""
    th = r.thetas
    step = th[1] - th[0]
    if peak.direction == "up":
        i = max(int(np.searchsorted(th, peak.theta - 1.5 * step)), 0)
        start, y0, s0 = th[i], r.up[i], r.up_sections[i]
        ts = np.linspace(start, min(start + 3 * step, th[-1]), points)[1:]
    else:
        i = min(int(np.searchsorted(th, peak.theta + 1.5 * step)), len(th) - 1)
        start, y0, s0 = th[i], r.down[i], r.down_sections[i]
        ts = np.linspace(start, max(start - 3 * step, th[0]), points)[1:]
    ys, _, _ = dz._settle_from(p, ts, s0, SweepSettings())
    j = int(np.nanargmax(ys))
    return (float(ts[j]), float(ys[j])) if ys[j] > y0 else (float(start), float(y0))


# Two impact suppressors whose downward sweep ends a periodic branch in a jump near its peak
# (theta ~1.081 and ~1.094): the zoom's bisection of the jump against the dense scan.
JUMP_CASES = [dict(gap=7.98, N=0.646, delta2=0.086, R=0.51), dict(gap=6.8, N=0.616, delta2=0.08, R=0.25)]


@pytest.mark.slow
@pytest.mark.parametrize(
    "kw, rank",
    [(dict(gap=2.0), 0), (dict(gap=2.0), 2), (dict(gap=-5.8), 0), (JUMP_CASES[0], "jump"), (JUMP_CASES[1], "jump")],
)
def test_located_peak_against_a_dense_local_scan(kw, rank):
    """The located peak (rank 0: the largest; 2: the other resonance; "jump": a periodic branch's
    end) against a continuation through 400 points across its grid bracket. (No periodic branch
    of the reference system ends in a jump inside the band: its jumps lie in nonperiodic
    stretches, where max|x1| is a window's and no tolerance applies; ``periodic`` says so.)"""
    p = Parameters(**kw)
    r = impact_band_response(p, BAND)
    peak = next(q for q in r.peaks if q.jump and q.periodic) if rank == "jump" else r.peaks[rank]
    assert peak.periodic and peak.jump == (rank == "jump")
    assert peak.bracket <= THETA_TOL and peak.change <= AMPLITUDE_RTOL
    t, v = _dense_scan(p, peak, r)
    scan_step = 3 * (r.thetas[1] - r.thetas[0]) / 400
    # The scan's largest is a sample 7.5e-5 from the next: at most the located value, and below it
    # by its tolerance on a smooth peak; at a jump (a fold, where the branch ends like a square
    # root) the last sample before the fold may lie up to a scan step short of it: 3e-4.
    assert v <= peak.value * (1 + AMPLITUDE_RTOL), (v, peak)
    assert v >= peak.value * (1 - (3e-4 if peak.jump else AMPLITUDE_RTOL)), (v, peak)
    assert abs(t - peak.theta) <= scan_step + THETA_TOL, (t, peak)
    if rank == 0:
        assert r.peak == peak.value and r.peak >= r.grid_peak()
        # The parabola through the grid's maximum and its neighbours: between the grid and the
        # located peak (to the latter's tolerance).
        assert r.grid_peak() <= r.interpolated_peak() <= r.peak * (1 + AMPLITUDE_RTOL)


def test_band_grid_policy():
    th = band_grid((0.5, 1.5))
    assert len(th) == 101 and th[0] == 0.5 and th[-1] == 1.5
    assert np.max(np.diff(band_grid((0.7, 1.234)))) <= dz.BAND_STEP
    with pytest.raises(ValueError, match="^`step` = "):
        band_grid(BAND, 0.0)


@pytest.mark.parametrize("mu", [0.02, 0.08, 0.2])
def test_tmd_optimum_against_den_hartog(mu):
    """An undamped object over a band holding both resonances: Den Hartog's tuning 1/(1 + mu)
    to 1e-3, his damping (delta2 = sqrt(3 mu/(8 (1 + mu)^3)) in this project's units) to 1.5 %,
    the peak within 0.5 % above the fixed points' height sqrt(1 + 2/mu), a lower bound."""
    o = optimise_tmd(mu, 0.0, (0.4, 1.6), budget=Budget(starts=16, keep=2, local_evaluations=200))
    dh = den_hartog(mu)
    assert dh["delta2"] == pytest.approx(math.sqrt(3 * mu / (8 * (1 + mu) ** 3)), rel=1e-14)
    assert abs(o.parameters["N"] / dh["N"] - 1) <= 1e-3
    assert abs(o.parameters["delta2"] / dh["delta2"] - 1) <= 1.5e-2
    assert dh["peak"] * (1 - 1e-12) <= o.peak <= 1.005 * dh["peak"]
    # The minimax optimum is at least as good as Den Hartog's own design.
    assert o.peak <= LinearDevice(mu, dh["N"], 0.0, dh["delta2"]).peak((0.4, 1.6))[1]


@pytest.mark.slow
def test_optimiser_against_a_brute_force_grid_on_a_small_box():
    """The TMD on a damped object: the optimiser's minimum over a small box is at most the
    best of an 81 x 81 grid of the box (and within 1e-3 of it: the grid's reach)."""
    bounds = {"N": (0.85, 0.97), "delta2": (0.08, 0.25)}
    band = (0.6, 1.4)
    f = lambda x: LinearDevice(0.08, x["N"], 0.05, x["delta2"]).peak(band)[1]  # noqa: E731
    x, v, n = minimise(f, f, bounds, budget=Budget(starts=8, keep=2, local_evaluations=200))
    grid = min(
        f({"N": a, "delta2": b}) for a in np.linspace(*bounds["N"], 81) for b in np.linspace(*bounds["delta2"], 81)
    )
    assert v <= grid * (1 + 1e-9)
    assert v >= grid * (1 - 1e-3)
    assert f(x) == v


def test_sensitivity_bisects_to_the_five_percent_line():
    f = lambda x: 1.0 + (x["a"] - 0.3) ** 2  # noqa: E731
    s = sensitivity(f, {"a": 0.3}, {"a": (0.0, 1.0)})
    # 5 % worse where (a - 0.3)^2 = 0.05: a move of sqrt(0.05) = 0.2236 each way; the down
    # side's bound (a move of 0.3) is already worse, the bisection finds it to 1/4096 of it.
    assert s["a"]["up"] == pytest.approx(math.sqrt(0.05), abs=1e-3)
    assert s["a"]["down"] == pytest.approx(math.sqrt(0.05), abs=1e-3)
    assert sensitivity(f, {"a": 0.3}, {"a": (0.2, 0.4)})["a"] == {"down": None, "up": None}


def test_detuning_maps_the_relative_parameters():
    """The object's natural frequency (1 + e) omega1: the detuned relative system's peak over
    the nominal x_st equals the TMD's |x1| computed directly in the nominal units."""
    mu, N, d1, d2, e = 0.08, 0.9, 0.05, 0.15, 0.07
    p = Parameters(mu=mu, N=N, delta1=d1, delta2=d2, gap=3.0)
    q, band, scale = detuned(p, BAND, e)
    assert (q.N, q.delta1, q.delta2, q.gap) == pytest.approx((N / 1.07, d1 / 1.07, d2 / 1.07, 3.0 * 1.07**2))
    # Directly: m1 x1'' + k1 x1' + c1 (1 + e)^2 x1 + absorber = P0 sin(omega t), in nominal units.
    th = np.linspace(*BAND, 2001)
    f2 = (1 + e) ** 2
    obj = f2 - th**2 + 2j * d1 * th
    b = N**2 + 2j * d2 * th
    direct = np.abs((b - th**2) / (obj * (b - th**2) - mu * b * th**2))
    mapped = scale * LinearDevice(mu, q.N, q.delta1, q.delta2).amplitude(th / (1 + e))
    assert np.max(np.abs(direct - mapped) / direct) <= 1e-12
    assert worst_case_tmd(mu, d1, N, d2, BAND, 0.0) == pytest.approx(LinearDevice(mu, N, d1, d2).peak(BAND)[1])
    with pytest.raises(ValueError, match="^`detuning` = "):
        detuned(p, BAND, -1.0)


def _run(*args):
    return subprocess.run(
        [sys.executable, "-m", "impactdamper", "design", *args], capture_output=True, text=True, timeout=300
    )


@pytest.mark.slow  # a fresh interpreter each, ~3 s
@pytest.mark.parametrize(
    "args, flag",
    [
        (["--mu", "0"], "--mu"),
        (["--delta1", "-0.1"], "--delta1"),
        (["--theta-start", "1.5", "--theta-stop", "1"], "--theta-stop"),
        (["--detuning", "0.9"], "--detuning"),
        (["--max-stroke", "0"], "--max-stroke"),
        (["--mu", "x"], "--mu"),
    ],
)
def test_design_command_bad_input_is_one_line(args, flag):
    r = _run(*args)
    assert r.returncode == 2 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and f"argument {flag}: " in lines[0], r.stderr


@pytest.mark.slow
def test_design_command_json_keys():
    r = _run(
        "--theta-start",
        "0.8",
        "--theta-stop",
        "1.2",
        "--mu",
        "0.05",
        "--delta1",
        "0.05",
        "--detuning",
        "0.05",
        "--json",
    )
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert {
        "band",
        "mu",
        "delta1",
        "detuning",
        "criterion",
        "impact",
        "tmd",
        "tmd_equal_stroke",
        "ratio",
        "elapsed",
    } <= set(out)
    for key in ("impact", "tmd", "tmd_equal_stroke"):
        assert {"parameters", "peak", "peak_theta", "band_average", "worst_case", "stroke", "at_bound"} <= set(out[key])
        assert out[key]["worst_case"] >= out[key]["peak"] * (1 - 1e-12)
    assert set(out["impact"]["parameters"]) == {"gap", "N", "delta2", "R"}
    assert {"impulse_per_impact", "impacts_per_second", "mean_force", "clearance"} <= set(out["impact"])
    assert out["tmd_equal_stroke"]["stroke"] <= out["impact"]["stroke"] * (1 + 1e-6)
    assert out["ratio"]["peak"] == pytest.approx(out["impact"]["peak"] / out["tmd"]["peak"])
    assert "impactdamper design: " in r.stderr  # progress lines


def _record(imp_peak, tmd_peak, imp_worst, tmd_worst, imp_avg=2.3, tmd_avg=2.3):
    def row(name, peak, worst, avg, stroke, **kw):
        return {
            "device": name,
            "peak": peak,
            "band_average": avg,
            "worst_case": {"0.1": worst},
            "stroke": stroke,
            **kw,
        }

    return {
        "detunings": [0.05, 0.1],
        "devices": [
            row("impact, optimal peak", tmd_peak, 9.0, 3.0, 9.5, parameters={"gap": 12.0}, impacts_per_second=0.0),
            row(
                "impact, optimal peak, gap <= 8",
                imp_peak,
                9.0,
                3.0,
                18.0,
                parameters={"gap": 4.77},
                impacts_per_second=1.1,
            ),
            row("TMD, optimal peak", tmd_peak, 9.0, 3.0, 9.5),
            row("impact, optimal band average", 9.0, 9.0, imp_avg, 1.0),
            row("TMD, optimal band average", 9.0, 9.0, tmd_avg, 1.0),
            row("impact, robust +-10 %", 9.0, imp_worst, 3.0, 1.0),
            row("TMD, robust +-10 %", 9.0, tmd_worst, 3.0, 1.0),
        ],
    }


@pytest.mark.parametrize(
    "values, first",
    [
        ((3.7, 3.6, 5.0, 4.6), "Build the linear TMD"),  # the TMD wins both
        ((3.7, 3.6, 4.0, 4.6), "Build the impact suppressor"),  # the robust impact suppressor wins the worst case
        ((3.6, 3.7, 4.60, 4.65), "Build the impact suppressor"),  # worst cases tie: the nominal peak decides
        ((3.60, 3.65, 4.60, 4.65), "Either device does"),  # ties within TIE on both
    ],
)
def test_recommendation_follows_the_record(values, first):
    from impactdamper.studies.design.optimum import recommendation

    text = recommendation(_record(*values))
    assert text.startswith(first + ":"), text
    assert "Delta0 = 4.77 P0/c1" in text and "\n" not in text
