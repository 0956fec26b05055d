"""Benettin's largest exponent on solve_ivp (impactdamper.baselines.benettin_ivp), the
independent check of the tangent walk: its conversion and impact law against the paper's
definitions, its free flow against the roots of the paper's characteristic equation (4), its
independence from the library's code, and (slow) its value at a chaotic point against the walk.
"""

import ast
import inspect
import math

import numpy as np
import pytest

from impactdamper.analysis.lyapunov import SIGNIFICANCE, lyapunov_spectrum
from impactdamper.baselines import benettin_ivp as module
from impactdamper.baselines.benettin_ivp import _ImpactOscillator, benettin_ivp, physical
from impactdamper.core.parameters import Parameters, state_scale

REF = dict(theta=1.0, mu=0.08, N=0.5, delta1=0.05, delta2=0.05, R=0.7)


def test_the_module_imports_nothing_of_the_library():
    """Independent means no flow, event, model or parameter code shared: no import of impactdamper."""
    tree = ast.parse(inspect.getsource(module))
    names = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    names += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    assert names and not [n for n in names if n.startswith("impactdamper") or n.startswith(".")], names


def test_conversion_gives_back_the_relative_parameters():
    c = physical(1.3, 0.08, 0.6, 0.05, 0.07, 0.7, -16.0, omega=12.0, x_st=0.5, m1=3.0)
    w1 = math.sqrt(c["c1"] / c["m1"])
    assert c["omega"] / w1 == pytest.approx(1.3, rel=1e-14)
    assert c["m2"] / c["m1"] == pytest.approx(0.08, rel=1e-14)
    assert math.sqrt(c["c2"] / c["m2"]) / w1 == pytest.approx(0.6, rel=1e-14)
    assert c["k1"] / (2 * c["m1"] * w1) == pytest.approx(0.05, rel=1e-14)
    assert c["k2"] / (2 * c["m2"] * w1) == pytest.approx(0.07, rel=1e-14)
    assert c["P0"] / c["c1"] == pytest.approx(0.5, rel=1e-14) and c["Delta0"] == -8.0


def test_an_impact_reverses_the_closing_velocity_times_R_and_keeps_momentum():
    osc = _ImpactOscillator(physical(**REF, gap=-16.0))
    c = osc.c
    y = np.array([0.3, 0.3 - 16.0, 1.0, 4.0])
    z = osc.strike(y)
    assert z[3] - z[2] == pytest.approx(-0.7 * (y[3] - y[2]), rel=1e-14)
    assert c["m1"] * z[2] + c["m2"] * z[3] == pytest.approx(c["m1"] * y[2] + c["m2"] * y[3], rel=1e-14)
    assert c["Delta0"] - (z[1] - z[0]) == 0.0
    with pytest.raises(RuntimeError, match="capture"):
        osc.strike(np.array([0.3, -15.7, 1.0, 1.0]))  # no closing velocity


def test_free_flow_exponent_is_the_least_damped_root_of_equation_4():
    """Far from the stop (gap +50: no impact) the largest exponent is max Re(lambda_j) T, lambda_j
    the roots of the paper's characteristic equation (4), d5 l^4 + d4 l^3 + d3 l^2 + d2 l + d1.
    Measured: -0.29775 +- 0.0064 against -0.29858 over 200 periods (0.13 errors)."""
    c = physical(**REF, gap=50.0)
    m1, m2, w1, w2 = c["m1"], c["m2"], 10.0, 5.0
    h1, h2 = c["k1"] / (2 * m1), c["k2"] / (2 * m2)
    d = [m1, 2 * (m1 * h1 + h2 * (m1 + m2)), m1 * (w1**2 + 4 * h1 * h2) + w2**2 * (m1 + m2)]
    d += [2 * m1 * (w2**2 * h1 + w1**2 * h2), m1 * w1**2 * w2**2]
    exact = max(np.roots(d).real) * 2 * math.pi / 10.0
    r = benettin_ivp(**REF, gap=50.0, start=[0, 0, 0, 0], transient=0, periods=200)
    assert r["impacts_per_period"] == 0.0
    assert abs(r["exponent"] - exact) <= SIGNIFICANCE * r["error"], (r, exact)
    assert r["error"] < 0.01


def test_bad_periods_are_named():
    with pytest.raises(ValueError, match="`periods`"):
        benettin_ivp(**REF, gap=-16.0, start=[0, -16, 0, 0], transient=0, periods=105)


@pytest.mark.slow
def test_chaotic_point_agrees_with_the_tangent_walk():
    """Gap -16 (chaotic, no captures): 300 periods of the two trajectories (about 3 CPU-s)
    against the walk's 2000, within SIGNIFICANCE combined errors."""
    p = Parameters(gap=-16.0)
    s = lyapunov_spectrum(p)
    assert s.label == "chaotic" and s.captures == 0
    r = benettin_ivp(**REF, gap=-16.0, start=s.sections[-1] / state_scale(p), transient=20, periods=300)
    assert r["exponent"] > 0.5
    assert abs(r["exponent"] - s.exponents[0]) <= SIGNIFICANCE * math.hypot(r["error"], s.errors[0]), (r, s.exponents)
