"""Thresholds shared by the reference event loop and its compiled copy.

:mod:`impactdamper.core.simulate` (the readable reference of Algorithm No. 2) and
:mod:`impactdamper.core.compiled.loop` (the same loop in numba) read these, so that the two
backends decide the same way at every contact switch (eqs. (20)-(22) of Timofeev et al.
(2019): impact, capture into persistent contact, lift-off). This module imports nothing of
the package; a change here changes both backends (and the numba cache, stamped with every
source of :mod:`impactdamper.core`, recompiles).
"""

from __future__ import annotations

__all__ = [
    "REBOUND_FLOOR",
    "DEPARTURE_FLOOR",
    "DEPARTURE_ULPS",
    "SAME_TIME_ULPS",
    "CURVATURE_FLOOR",
    "STEPS_PER_PERIOD",
    "STEPS_AT_START",
]

# A rebound velocity (relative, after an impact) above REBOUND_FLOOR * length_scale * omega_max
# opens the gap at first order; below it the rebound is rounding of a plastic or grazing impact
# (the velocities are known to ~1e-16 of x_st omega, so 1e-14 leaves a 100-fold margin), and
# the departure is decided by the gap's higher derivatives.
REBOUND_FLOOR = 1e-14
# The gap's m-th derivative (m = 2, 3, 4) leaving the stop counts as non-zero above
# DEPARTURE_FLOOR * length_scale * omega_max**m: two orders above REBOUND_FLOOR, since each
# derivative of the exact flow carries the rounding of the previous one times omega.
DEPARTURE_FLOOR = 1e-12
# An event time is known to ~ulp(t); one ulp of t moves g^(m) by g^(m+1) ulp(t). Below
# DEPARTURE_ULPS times that, g^(m) is rounding noise, not a departure (at t ~ 382 s, gap -19,
# step 608, order 2 gave a first step below ulp(t) and 50 zero-velocity impacts followed):
# 8 ulps cover the rounding of the derivative's evaluation as well as of t.
DEPARTURE_ULPS = 8.0
# Two events within SAME_TIME_ULPS ulps of t of each other are at the same time (an impact and
# the capture it triggers): the guard against degenerate contact counts them, and
# MAX_EVENTS_AT_ONE_TIME of them stop the run. 4 ulps: the polished root is accurate to 1-2 ulps.
SAME_TIME_ULPS = 4
# A contact force that touched zero without changing sign is stepped past with its curvature
# F'' as the departure value; F'' is floored at CURVATURE_FLOOR (a positive tiny number, far
# below any physical F'') so that the search's Taylor bound stays finite and positive.
CURVATURE_FLOOR = 1e-300
# The work bound of one run: certified search steps allowed per forcing period advanced, plus
# an allowance at the start (the reference's StepBudget, the kernels' budget). Ordinary motions
# take 5-600 steps per period on average (a chatter sequence or a search at the lift-off
# threshold a few thousand at once); a motion far faster or stiffer than the forcing (theta =
# 1e-5: 2e5 steps in its first period) ends in a SearchLimitError within seconds instead of
# running for minutes. Every event and contact switch costs a step, so this bounds them too.
STEPS_PER_PERIOD = 20_000
STEPS_AT_START = 20_000
