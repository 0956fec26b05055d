"""The compiled solver's array layout: the codes and indices its kernels share.

The kernels of :mod:`impactdamper.core.compiled` pass numbers, not objects: a parameter set is
a few arrays (:class:`~impactdamper.core.compiled.pack.Pack`), a run's state two small vectors,
an event or a mode an integer. This module names those integers.
"""

from __future__ import annotations

__all__ = ["EVENT_KINDS", "FALLBACK_REASONS"]

EVENT_KINDS = ("impact", "stick", "liftoff")
# Event kinds, as indices into EVENT_KINDS.
IMPACT, STICK, LIFTOFF = 0, 1, 2
# Contact modes: the bodies apart (the free mode, 4 states) or moving together (2 states).
MODE_FREE, MODE_STUCK = 0, 1
# The functionals of the pack: the gap on the free mode, the contact force on the stuck mode,
# and minus the contact force (the brief-dip search of the reference's _dip_unresolved).
GAP, FORCE, NEG_FORCE = 0, 1, 2
# Kernel outcomes. 0 is success; the errors mirror the reference's exceptions (which the
# wrapper then raises by re-running the reference), CAPACITY asks for larger event buffers.
OK, ERR_BUDGET, ERR_SEARCH, ERR_DEGENERATE, ERR_STUCK_RESONANT, ERR_CAPACITY = 0, 1, 2, 3, 4, 5
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
# budget used, last event time]; si = [mode, departure order (0: none), same-time events,
# events, segments, record flag, error]; y0 (4,) and alpha (4,) of the segment.
SF_T0, SF_FROM, SF_DEPG, SF_START, SF_LIMIT, SF_USED, SF_LAST = range(7)
SI_MODE, SI_DEPM, SI_SAME, SI_NEV, SI_NSEG, SI_REC, SI_ERR = range(7)
