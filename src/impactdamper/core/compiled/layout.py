"""The compiled solver's array layout: the codes and indices its kernels share.

The kernels of :mod:`impactdamper.core.compiled` pass numbers, not objects: a parameter set is
a few arrays (:class:`~impactdamper.core.compiled.pack.Pack`), a run's state two small vectors,
an event or a mode an integer. This module names those integers.
"""

from __future__ import annotations

from impactdamper.core.trajectory import EVENT_KINDS, MODE_NAMES

__all__ = ["FALLBACK_REASONS"]

# Event kinds, as indices into the reference's EVENT_KINDS.
IMPACT, STICK, LIFTOFF = (EVENT_KINDS.index(k) for k in ("impact", "stick", "liftoff"))
# Contact modes, as indices into the reference's MODE_NAMES: the bodies apart (the free mode,
# 4 states) or moving together (2 states).
MODE_FREE, MODE_STUCK = (MODE_NAMES.index(m) for m in ("free", "stuck"))
# The functionals of the pack: the gap on the free mode, the contact force on the stuck mode,
# and minus the contact force (the brief-dip search of the reference's _dip_unresolved).
GAP, FORCE, NEG_FORCE = 0, 1, 2
# What a march returns besides an error: no root in the interval, or a root.
MARCH_NONE, MARCH_ROOT = 0, 1
# Kernel outcomes. 0 is success; the errors mirror the reference's exceptions (numbered above
# the march's statuses, so that a march's error is never read as a root): the work bound (the
# step budget, which bounds the events and contact switches per period), a search that failed
# (a step count or a bound beyond range), more than MAX_EVENTS_AT_ONE_TIME events at one time,
# a resonance in contact, and a recorded run whose events outgrew the buffers the work bound
# allows (never expected: every event costs a certified step, see loop.recorded_run), and a
# tangent walk whose contact mode disagrees with the loop's at a period's end (never expected,
# see tangent.tangent_kernel).
OK, ERR_BUDGET, ERR_SEARCH, ERR_DEGENERATE, ERR_STUCK_RESONANT, ERR_CAPACITY, ERR_WALK = 0, 2, 3, 4, 5, 6, 7
# The errors of the work bound, which the backend reports with the reference's message (built
# from the run's diagnostics, see DIAG_*) instead of running the reference to its bound.
WORK_BOUND_ERRORS = (ERR_BUDGET, ERR_DEGENERATE)
# Why a point was not solved by the kernels (see the package docstring).
FALLBACK_REASONS = ("", "matrix_exponential", "scales", "error", "rescue")
# Scalars of the pack (Pack.s), by index.
(
    S_OMEGA,
    S_T,
    S_DELTA0,
    S_R,
    S_M1,
    S_M2,
    S_MRED,
    S_OMEGA1,
    S_LSCALE,
    S_FSCALE,
    S_GAP_EPS,
    S_CHATTER,
    S_FORCE_EPS,
    S_STUCK_RES,
    S_XST,
    N_SCALARS,
) = range(16)
# A solver's state: sf = [segment t0, search_from, departure value, run start, budget limit,
# budget used, last event time, time of the error]; si = [mode, departure order (0: none),
# same-time events, events, segments, record flag, error, impacts in a row since the last other
# event]; y0 (4,) and alpha (4,) of the segment.
SF_T0, SF_FROM, SF_DEPG, SF_START, SF_LIMIT, SF_USED, SF_LAST, SF_ERRT = range(8)
SI_MODE, SI_DEPM, SI_SAME, SI_NEV, SI_NSEG, SI_REC, SI_ERR, SI_IMPACTS = range(8)
# A failed run's diagnostics (the kernels' ``diag`` output), from which the backend words the
# reference's message: certified steps used, the time of the error and the run's start (s), the
# impacts in a row at the end (a chatter sequence), and the error code.
DIAG_USED, DIAG_TIME, DIAG_START, DIAG_IMPACTS, DIAG_ERR, N_DIAG = range(6)
