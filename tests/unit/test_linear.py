"""The linear part: eq. (4), eq. (5), eqs. (10)-(11), and the exact flow between events,
each against an independent derivation."""

import math

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg
import scipy.optimize

from helpers import REF, free_rhs, mck, stuck_rhs

import impactdamper.core.linear as linear
from impactdamper import Parameters
from impactdamper.core.linear import (
    characteristic_coefficients,
    characteristic_roots,
    forced_amplitudes,
    free_mode,
    mode_shape_ratios,
    stuck_mode,
)

CASES = {
    "reference": REF,
    "heavy_damping_real_roots": REF.replace(delta1=2.0, delta2=5.0),
    "zero_damping": REF.replace(delta1=0.0, delta2=0.0),
    "light_damping": REF.replace(delta1=1e-3, delta2=1e-3),
    "mu_1e-4": REF.replace(mu=1e-4),
    "N_50": REF.replace(N=50.0),
    "theta_0.1_m1_37.5": REF.replace(theta=0.1, m1=37.5),
    "theta_10_x_st_0.01": REF.replace(theta=10.0, x_st=0.01),
}


def quartic_discriminant(c):
    a, b, c, d, e = c
    return (
        256 * a**3 * e**3
        - 192 * a**2 * b * d * e**2
        - 128 * a**2 * c**2 * e**2
        + 144 * a**2 * c * d**2 * e
        - 27 * a**2 * d**4
        + 144 * a * b**2 * c * e**2
        - 6 * a * b**2 * d**2 * e
        - 80 * a * b * c**2 * d * e
        + 18 * a * b * c * d**3
        + 16 * a * c**4 * e
        - 4 * a * c**3 * d**2
        - 27 * b**4 * e**2
        + 18 * b**3 * c * d * e
        - 4 * b**3 * d**3
        - 4 * b**2 * c**3 * e
        + b**2 * c**2 * d**2
    )


def repeated_root_parameters() -> Parameters:
    """delta2 where the suppressor's complex pair of eq. (4) becomes a real pair (a double
    real root): the root of the quartic's discriminant (in lambda/omega1) between 0.4 and 0.5."""

    def disc(d2):
        p = REF.replace(delta2=d2)
        c = characteristic_coefficients(p)
        return quartic_discriminant(c / c[0] * p.omega1 ** -np.arange(5.0))

    d2 = scipy.optimize.brentq(disc, 0.4, 0.5, xtol=1e-17, rtol=1e-15)
    return REF.replace(delta2=d2)


REPEATED = repeated_root_parameters()


def matched(a, b):
    """The entries of a reordered to pair up with the nearest entries of b."""
    rows, cols = scipy.optimize.linear_sum_assignment(np.abs(a[:, None] - b[None, :]))
    out = np.empty_like(b)
    out[cols] = a[rows]
    return out


# --- closed forms first ----------------------------------------------------------------------


def test_zero_damping_roots_are_the_biquadratic_closed_form():
    # delta = 0: m1 m2 l^4 + (m1 c2 + m2 (c1 + c2)) l^2 + c1 c2 = 0 (det of K + l^2 M).
    p = CASES["zero_damping"]
    a, b, c = p.m1 * p.m2, p.m1 * p.c2 + p.m2 * (p.c1 + p.c2), p.c1 * p.c2
    s = np.sqrt(b * b - 4 * a * c)
    Om = np.sqrt(np.array([(b + s) / (2 * a), (b - s) / (2 * a)]))
    roots = characteristic_roots(p)
    assert np.max(np.abs(roots.real)) <= 1e-13 * p.omega1
    assert np.sort(np.abs(roots.imag)) == pytest.approx(np.sort(np.concatenate([Om, Om])), rel=1e-13)
    d = characteristic_coefficients(p)
    assert d[1] == 0 and d[3] == 0


def test_stuck_mode_is_the_one_mass_oscillator():
    # (m1 + m2) x'' + k1 x' + c1 x = P0 sin(wt): roots and forced amplitude in closed form.
    p = REF
    m = p.m1 + p.m2
    mode = stuck_mode(p)
    roots = np.roots([m, p.k1, p.c1])
    assert matched(mode.roots, roots) == pytest.approx(roots, rel=1e-14)
    xhat = p.P0 / (p.c1 - m * p.omega**2 + 1j * p.omega * p.k1)
    assert mode.Yhat == pytest.approx([xhat, 1j * p.omega * xhat], rel=1e-14)
    # The free decay from (1, 0): e^{-ht}(cos wd t + h/wd sin wd t).
    h, wd = p.k1 / (2 * m), math.sqrt(p.c1 / m - (p.k1 / (2 * m)) ** 2)
    tau = np.linspace(0, 3 * p.T, 7)
    exact = np.exp(-h * tau) * (np.cos(wd * tau) + h / wd * np.sin(wd * tau))
    assert mode.free(tau, np.array([1.0, 0.0]))[:, 0] == pytest.approx(exact, abs=1e-14)


# --- eq. (4) and eq. (5) ---------------------------------------------------------------------


@pytest.mark.parametrize("name", CASES)
def test_characteristic_polynomial_is_det_of_the_dynamic_stiffness(name):
    # Substituting (3) in (2) gives det(l^2 M + l C + K) = 0; eq. (4) is that over m2.
    p = CASES[name]
    mass, damping, stiffness = mck(p)
    d = characteristic_coefficients(p)
    for lam in (0.3 + 0.7j, -1.1 + 2.0j, 2.5):
        lam = lam * p.omega1
        det = np.linalg.det(lam**2 * mass + lam * damping + stiffness) / p.m2
        assert np.polyval(d, lam) == pytest.approx(det, rel=1e-12, abs=1e-12 * abs(d[0] * lam**4))


@pytest.mark.parametrize("name", CASES)
def test_roots_of_eq4_are_the_eigenvalues_of_the_state_matrix(name):
    p = CASES[name]
    mass, damping, stiffness = mck(p)
    Minv = np.linalg.inv(mass)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ stiffness, -Minv @ damping]])
    eig = np.linalg.eigvals(A)
    scale = np.max(np.abs(eig))
    assert np.max(np.abs(matched(characteristic_roots(p), eig) - eig)) <= 1e-10 * scale
    assert np.max(np.abs(matched(free_mode(p).roots, eig) - eig)) <= 1e-12 * scale


@pytest.mark.parametrize("name", CASES)
def test_mode_shape_ratios_eq5_are_the_eigenvector_ratios(name):
    p = CASES[name]
    mass, damping, stiffness = mck(p)
    Minv = np.linalg.inv(mass)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ stiffness, -Minv @ damping]])
    lam, V = np.linalg.eig(A)
    ratios = mode_shape_ratios(p, lam)
    # (1, A_j, l_j, A_j l_j) is parallel to numpy's eigenvector j: |cos angle| = 1
    W = np.array([np.ones_like(lam), ratios, lam, ratios * lam])
    W /= np.linalg.norm(W, axis=0)
    cos = np.abs(np.sum(np.conj(W) * V, axis=0)) / np.linalg.norm(V, axis=0)
    assert np.all(np.abs(cos - 1.0) <= 1e-12)
    # and the second line of eq. (2) holds for x1s = e^{lt}, x2s = A e^{lt}
    terms = [p.m2 * lam**2 * ratios, p.k2 * lam * (ratios - 1), p.c2 * (ratios - 1)]
    # (A - 1) cancels where A ~ 1 (stiff suppressor, N = 50): a looser bound there
    assert np.all(np.abs(sum(terms)) <= 1e-11 * sum(np.abs(t) for t in terms))


def test_repeated_roots_are_found_and_the_modal_form_is_left():
    p = REPEATED
    roots = characteristic_roots(p)
    real = roots[np.abs(roots.imag) < 1e-6 * p.omega1]
    assert len(real) == 2
    assert abs(real[0] - real[1]) <= 1e-6 * p.omega1  # a double root, to rounding
    mode = free_mode(p)
    assert not mode.modal  # the eigenvector matrix is (numerically) singular
    assert np.linalg.cond(mode.eigenvectors) > 1e6
    assert free_mode(REF).modal


# --- eqs. (10)-(11): the forced response ------------------------------------------------------


@pytest.mark.parametrize("name", CASES)
def test_forced_response_eq10_satisfies_eq9(name):
    p = CASES[name]
    x1, x2 = forced_amplitudes(p)
    w = p.omega
    t = np.linspace(0, p.T, 11)
    # eq. (11): x_ip(t) = |x_ip| sin(w t + arg x_ip)
    X = np.array([abs(x1) * np.sin(w * t + np.angle(x1)), abs(x2) * np.sin(w * t + np.angle(x2))])
    V = np.array([abs(x1) * w * np.cos(w * t + np.angle(x1)), abs(x2) * w * np.cos(w * t + np.angle(x2))])
    Acc = -w * w * X
    mass, damping, stiffness = mck(p)
    resid = mass @ Acc + damping @ V + stiffness @ X - np.array([p.P0 * np.sin(w * t), 0 * t])
    assert np.max(np.abs(resid)) <= 1e-12 * p.P0 * max(1.0, abs(x1) / p.x_st, abs(x2) / p.x_st)
    # the library's state-space forced response is the same
    Y = free_mode(p).forced(t)
    assert np.max(np.abs(Y[:, :2] - X.T)) <= 1e-12 * max(abs(x1), abs(x2))
    assert np.max(np.abs(Y[:, 2:] - V.T)) <= 1e-12 * w * max(abs(x1), abs(x2))


@pytest.mark.parametrize("mode_fn", [free_mode, stuck_mode])
def test_forced_state_derivative_is_the_rhs(mode_fn):
    mode = mode_fn(REF)
    t = np.linspace(0, REF.T, 9)
    lhs = mode.forced(t, derivative=1)
    rhs = mode.rhs(t, mode.forced(t))
    assert np.max(np.abs(lhs - rhs)) <= 1e-12 * np.max(np.abs(rhs))


# --- the exact flow ---------------------------------------------------------------------------


def _tight_ivp(f, t0, t1, y0, t_eval):
    sol = scipy.integrate.solve_ivp(f, (t0, t1), y0, method="DOP853", rtol=1e-13, atol=1e-14, t_eval=t_eval)
    assert sol.success
    return sol.y.T


@pytest.mark.parametrize("name", list(CASES) + ["repeated"])
def test_free_flow_matches_solve_ivp(name):
    p = REPEATED if name == "repeated" else CASES[name]
    mode = free_mode(p)
    y0 = np.array([0.3, -1.2, 2.0, -5.0]) * p.x_st * np.array([1, 1, p.omega1, p.omega1])
    t0 = 0.37 * p.T
    t = t0 + np.linspace(0.0, 2.0, 9) * 2 * math.pi / p.omega1
    exact = mode.state(t, t0, y0)
    ref = _tight_ivp(free_rhs(p), t0, t[-1], y0, t)
    scale = np.max(np.abs(ref), axis=0)
    assert np.all(np.abs(exact - ref) <= 1e-10 * scale)


def test_stuck_flow_matches_solve_ivp():
    p = REF
    mode = stuck_mode(p)
    y0 = np.array([1.5, -20.0])
    t = 0.1 + np.linspace(0, 3 * p.T, 13)
    ref = _tight_ivp(stuck_rhs(p), t[0], t[-1], y0, t)
    exact = mode.state(t, t[0], y0)
    assert np.all(np.abs(exact - ref) <= 1e-10 * np.max(np.abs(ref), axis=0))


@pytest.mark.parametrize("name", ["reference", "heavy_damping_real_roots", "zero_damping", "repeated"])
def test_flow_satisfies_the_ode_by_finite_differences(name):
    p = REPEATED if name == "repeated" else CASES[name]
    mode = free_mode(p)
    f = free_rhs(p)
    y0 = np.array([1.0, 2.0, -3.0, 40.0])
    h = 1e-4 * p.T
    for t in np.linspace(0.05, 2.0, 5) * p.T:
        y = mode.state(np.array([t - 2 * h, t - h, t + h, t + 2 * h]), 0.0, y0)
        # 4th-order central difference: error ~ h^4 y^(5) / 30
        dy = (y[0] - 8 * y[1] + 8 * y[2] - y[3]) / (12 * h)
        ref = f(t, mode.state(t, 0.0, y0))
        assert np.all(np.abs(dy - ref) <= 1e-8 * np.max(np.abs(ref)))


@pytest.mark.parametrize("name", ["reference", "zero_damping", "repeated"])
def test_flow_is_a_semigroup(name):
    p = REPEATED if name == "repeated" else CASES[name]
    mode = free_mode(p)
    y0 = np.array([0.5, -0.5, 3.0, -7.0])
    y1 = mode.state(1.3, 0.2, y0)
    direct = mode.state(2.9, 0.2, y0)
    assert mode.state(2.9, 1.3, y1) == pytest.approx(direct, rel=1e-11, abs=1e-12 * np.max(np.abs(direct)))


def test_zero_damping_free_motion_keeps_its_energy():
    p = CASES["zero_damping"]
    mode = free_mode(p)
    z0 = np.array([0.3, -2.0, 4.0, 9.0])
    z = mode.free(np.linspace(0, 50 * p.T, 101), z0)
    e = mode.energy(z)
    assert np.max(np.abs(e - e[0])) <= 1e-12 * e[0]


@pytest.mark.parametrize("name", ["reference", "heavy_damping_real_roots", "light_damping", "N_50"])
def test_modal_and_expm_paths_agree(name, monkeypatch):
    p = CASES[name]
    modal = free_mode(p)
    assert modal.modal
    monkeypatch.setattr(linear, "MODAL_CONDITION_LIMIT", 0.0)  # force the matrix exponential
    linear._clear_mode_cache()  # (the cached modal one would be returned)
    try:
        expm = free_mode(p)
    finally:
        linear._clear_mode_cache()  # (nor may the expm one outlive the patch)
    assert not expm.modal
    tau = np.linspace(0, 3 * p.T, 7)
    Pm, Pe = modal.propagator(tau), expm.propagator(tau)
    assert np.max(np.abs(Pm - Pe)) <= 1e-11 * np.max(np.abs(Pe))
    direct = np.array([scipy.linalg.expm(modal.M * s) for s in tau])
    assert np.max(np.abs(Pm - direct)) <= 1e-11 * np.max(np.abs(direct))
    y0 = np.array([1.0, -3.0, 20.0, 5.0])
    a, b = modal.state(tau, 0.1, y0), expm.state(tau, 0.1, y0)
    assert np.max(np.abs(a - b)) <= 1e-11 * np.max(np.abs(b))


def test_modes_are_shared_by_parameters_that_differ_only_in_gap_and_R():
    """free_mode and stuck_mode depend on neither Delta0 nor R: they are built once per set of
    the other values (a cache), and equal a fresh construction."""
    from impactdamper.core.linear import _free_mode, free_mode, stuck_mode

    p = Parameters()
    q = p.replace(gap=3.0, R=0.2)
    assert free_mode(p) is free_mode(q) and stuck_mode(p) is stuck_mode(q)
    assert free_mode(p) is not free_mode(p.replace(theta=1.1))
    fresh = _free_mode.__wrapped__(p.m1, p.m2, p.c1, p.c2, p.k1, p.k2, p.P0, p.omega)
    assert np.array_equal(fresh.roots, free_mode(p).roots) and np.array_equal(fresh.Yhat, free_mode(p).Yhat)
    c = np.array([1.0, -1.0, 0.0, 0.0])
    assert free_mode(p).derivative_bound_factor(c, 2) == fresh.derivative_bound_factor(c, 2)


@pytest.mark.parametrize(
    "scales",
    [dict(omega=1e4), dict(omega=2e4), dict(omega=1e-8), dict(omega=1e10), dict(omega=1e-10), dict(theta=1e-9)],
)
def test_the_modal_test_does_not_depend_on_the_rate(scales):
    """cond(V) in (x, v) units grew with the rate (2.4e4 at omega 2e4, 1.2e10 at theta 1e-9), and
    points inside the native range left the kernels for repeated roots they did not have. In
    the mode's own units the condition is that of the relative problem: the reference case's
    (2.3 free, 1.05 stuck) to 1e-6 relative, at every rate, both modes modal."""
    from impactdamper.core.linear import _clear_mode_cache, scaled_condition

    _clear_mode_cache()
    for mode in (free_mode, stuck_mode):
        ref, m = mode(REF), mode(REF.replace(**scales))
        ratio = [scaled_condition(*np.linalg.eig(x.M)[::-1]) for x in (ref, m)]
        assert ratio[1] == pytest.approx(ratio[0], rel=1e-6)
        assert m.modal and ratio[1] < 10.0


def test_the_modal_test_still_refuses_a_double_root():
    # A double root: the eigenvectors of the two coalescing modes align in any units.
    from impactdamper.core.linear import scaled_condition

    M = np.array([[0.0, 1.0], [-1.0, -2.0]])  # (s + 1)^2
    lam, V = np.linalg.eig(M)
    assert scaled_condition(V, lam) > 1e6
