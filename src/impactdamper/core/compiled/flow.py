"""The exact flow between events, compiled: eqs. (10)-(11) and (18)-(19) in modal form.

Between two events the state of a contact mode is the periodic forced response Y(t) of eqs.
(10)-(11) plus the free response V (alpha e^{lambda (t - t0)}), with alpha_j of eq. (19) fixed
at the segment's start (:class:`impactdamper.core.linear.LinearMode`, here on the packed arrays
``cm``). The functionals (the gap, eq. (20), and the contact force) are evaluated from the same
modal sums (:class:`impactdamper.core.events.Segment`'s evaluator) or from a state and its
derivatives (:meth:`impactdamper.core.events.LinearFunctional.of_state`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.layout import MODE_FREE, S_DELTA0, S_OMEGA


# The hot path (a march step, an impact, a segment start) is inlined into its callers at numba's
# IR level (inline="always"): measured 3.5 -> 2.5 us per impact, for about 20 s more compile time
# (the warm-up from an empty cache, 64 -> 85 s).


@njit(cache=True, inline="always")
def mode_size(mode):
    return 4 if mode == MODE_FREE else 2


@njit(cache=True, inline="always")
def modal_coefficients(cm, s, mode, t0, y0, alpha):
    """alpha = V^-1 (y0 - Y(t0)), eq. (19)."""
    n = mode_size(mode)
    rot = np.exp(1j * s[S_OMEGA] * t0)
    z0 = np.empty(4)
    for i in range(n):
        z0[i] = y0[i] - (rot * cm[mode, 1, i]).imag
    for i in range(n):
        acc = 0j
        for j in range(n):
            acc += cm[mode, 6 + i, j] * z0[j]
        alpha[i] = acc


@njit(cache=True, inline="always")
def free_part(cm, mode, alpha, tau, out):
    """z(tau) = Re V (alpha e^{lambda tau}), the free response."""
    # Summed over j in the same order as Re(V e) (the real part of a complex sum is the sum of
    # the real parts), without a temporary array: this is the state's hot path.
    n = mode_size(mode)
    for i in range(n):
        out[i] = 0.0
    for j in range(n):
        e = alpha[j] * np.exp(cm[mode, 0, j] * tau)
        for i in range(n):
            out[i] += (cm[mode, 2 + i, j] * e).real


@njit(cache=True, inline="always")
def mode_state(cm, s, mode, t0, alpha, t, out):
    """The mode's state at t, eq. (18): forced response plus free response."""
    n = mode_size(mode)
    free_part(cm, mode, alpha, t - t0, out)
    rot = np.exp(1j * s[S_OMEGA] * t)
    for i in range(n):
        out[i] += (cm[mode, 1, i] * rot).imag


@njit(cache=True, inline="always")
def full_state(s, mode, y, out):
    """(x1, x2, x1', x2') from a state of either mode."""
    if mode == MODE_FREE:
        for i in range(4):
            out[i] = y[i]
    else:
        out[0], out[1], out[2], out[3] = y[0], y[0] + s[S_DELTA0], y[1], y[1]


@njit(cache=True, inline="always")
def evaluate(cm, fc, fg, s, f, mode, t0, alpha, t):
    """(g(t), g'(t)) of functional f on the segment: the modal sums over one root of each
    conjugate pair (the reference's Segment.evaluator)."""
    n = mode_size(mode)
    tau = t - t0
    s0 = 0j
    s1 = 0j
    for j in range(n):
        lam = cm[mode, 0, j]
        if lam.imag < 0.0:
            continue
        b = fg[f, 1 + j] * alpha[j]
        if lam.imag > 0.0:
            b = 2.0 * b
        e = b * np.exp(lam * tau)
        s0 += e
        s1 += lam * e
    w = s[S_OMEGA]
    rot = np.exp(1j * w * t) * fg[f, 0]
    return fc[f, 6, 0] + rot.imag + s0.real, w * rot.real + s1.real


@njit(cache=True, inline="always")
def of_state(fc, s, f, mode, t, y, derivative):
    """g^(derivative)(t) from a state y, using y' = M y + b sin(omega t)."""
    n = mode_size(mode)
    w = s[S_OMEGA]
    if derivative == 0:
        acc = 0.0
        for i in range(n):
            acc += y[i] * fc[f, 0, i]
        return fc[f, 6, 0] + fc[f, 6, 1] * math.sin(w * t) + acc
    value = 0.0
    for i in range(n):
        value += y[i] * fc[f, derivative, i]
    for j in range(derivative):
        value = value + fc[f, 7, derivative - 1 - j] * w**j * math.sin(w * t + j * math.pi / 2)
    return value + fc[f, 6, 1] * w**derivative * math.sin(w * t + derivative * math.pi / 2)
