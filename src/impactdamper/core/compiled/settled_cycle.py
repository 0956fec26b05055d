"""The settled cycle described, compiled: its regime, impacts, contact fraction, x1_max and section.

The reference's :func:`impactdamper.core.settled_cycle.describe_cycle` on the describing run's
arrays (events and segments, as :func:`~impactdamper.core.compiled.loop.recorded_run` records
them): the cycle starts at the impact that ends its longest free flight, its events are counted as the
reference's ``_cycle_events`` counts them, its largest excursion is
:func:`~impactdamper.core.compiled.excursion.max_excursion`'s, and the section it hands on is
the state at its first forcing section.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactdamper.core.compiled.excursion import max_excursion, segment_index
from impactdamper.core.compiled.flow import full_state, mode_state
from impactdamper.core.compiled.layout import IMPACT, MODE_STUCK, S_T

# Regime codes: indices into settled_cycle.REGIMES (the nonperiodic one public: a row of points stops
# at it for the rescue, compiled.settle.row_kernel).
_RG_NO_CONTACT, _RG_STUCK, _RG_CHATTER, _RG_SINGLE, _RG_MULTI, RG_NONPERIODIC = range(6)


@njit(cache=True)
def _sample(cm, s, seg_m, seg_f, seg_a, ns, t, out, y):
    """Full state at t (into out; y is scratch), and the mode there."""
    k = segment_index(seg_f, ns, t)
    mode_state(cm, s, seg_m[k], seg_f[k, 0], seg_a[k], t, y)
    full_state(s, seg_m[k], y, out)
    return seg_m[k]


@njit(cache=True)
def describe_cycle(cm, s, ev_k, ev_f, ne, seg_m, seg_f, seg_a, ns, window_start, k, settled, out_imp, section):
    """The compiled counterpart of :func:`impactdamper.core.settled_cycle.describe_cycle`. Fills out_imp
    rows (t, t/T since start, phase, velocity, impulse) and section (state at the first section in
    the cycle, then its mode).
    Returns (regime code, impacts, cycle start, contact fraction, x1_max)."""
    T = s[S_T]
    Tc = k * T
    window_end = window_start + Tc
    start = window_start
    best_flight = -math.inf
    t_begin = seg_f[0, 0]
    for i in range(ne):
        if ev_k[i] == IMPACT and window_start <= ev_f[i, 0] < window_end:
            flight = ev_f[i, 0] - (ev_f[i - 1, 0] if i else t_begin)
            if flight > best_flight:
                best_flight = flight
                start = ev_f[i, 0]
    # The cycle's events (the reference's _cycle_events): [start, start + T_c - flight / 2)
    # after the start impact's (longest) flight, never a window with a fixed margin, which a
    # loose settle_tol's drift per period made count one impact twice; without impacts, or for
    # no cycle, [start, start + T_c).
    end_t = start + Tc
    if settled and best_flight > -math.inf:
        end_t = start + Tc - 0.5 * best_flight
    first = ne
    end = ne
    for i in range(ne):
        if first == ne and ev_f[i, 0] >= start:
            first = i
        if ev_f[i, 0] >= end_t:
            end = i
            break
    if end < first:
        end = first
    z = 0
    contact_events = False
    for i in range(first, end):
        t = ev_f[i, 0]
        if ev_k[i] == IMPACT:
            if z < out_imp.shape[0]:
                out_imp[z, 0] = t
                out_imp[z, 1] = (t - start) / T
                out_imp[z, 2] = (t / T) % 1.0
                out_imp[z, 3] = ev_f[i, 1]
                out_imp[z, 4] = ev_f[i, 2]
            z += 1
        else:
            contact_events = True
    contact_time = 0.0
    a, b = start, start + Tc
    for i in range(ns):
        if seg_m[i] != MODE_STUCK:
            continue
        s1 = seg_f[i + 1, 0] if i + 1 < ns else math.inf
        lo, hi = max(seg_f[i, 0], a), min(s1, b)
        if hi > lo:
            contact_time += hi - lo
    contact_fraction = min(contact_time / Tc, 1.0)
    if not settled:
        regime = RG_NONPERIODIC
    elif contact_fraction >= 1.0 - 1e-12 and z == 0:
        regime = _RG_STUCK
    elif z == 0 and contact_fraction == 0.0:
        regime = _RG_NO_CONTACT
    elif contact_events or contact_fraction > 0.0:
        regime = _RG_CHATTER
    elif k == 1 and z == 1:
        regime = _RG_SINGLE
    else:
        regime = _RG_MULTI
    x1_max = max_excursion(cm, s, seg_m, seg_f, seg_a, ns, start, start + Tc)
    t_sec = math.ceil(start / T - 1e-9) * T
    full = np.empty(4)
    section[4] = _sample(cm, s, seg_m, seg_f, seg_a, ns, t_sec, full, np.empty(4))
    section[:4] = full
    return regime, z, start, contact_fraction, x1_max
