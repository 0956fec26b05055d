"""The exact event-driven solver, compiled: Algorithm No. 2 and the settled motion in numba.

The same algorithm as the readable reference, step for step, with the same constants:

* the exact flow between events, eq. (18) with alpha_j of eq. (19) in modal form, and the
  periodic forced response of eqs. (10)-(11) (:mod:`impactdamper.core.linear`);
* the certified root march of the gap, eq. (20), and of the contact force, with the same
  Taylor lower bound, departure orders, Newton polish and step budget
  (:mod:`impactdamper.core.events`);
* the impact law of eqs. (21)-(22), the capture into persistent contact, lift-off, the
  brief-dip rule and grazing (:mod:`impactdamper.core.simulate`);
* the stroboscopic sections, the period test with its divisor rule, the re-basing of the
  clock and the description of the cycle (:mod:`impactdamper.core.settled_cycle`).

The matrices (modal eigenvectors, forced amplitudes, derivative-bound factors) are computed once
per parameter set with the operations of the reference classes
(:class:`~impactdamper.core.model.Model`) and packed into arrays; the kernels only evaluate. Whatever the kernels do not reproduce falls back to the
pure-Python solver, and the result says so (``fallback``):

* a mode whose eigenvector matrix, in the mode's own units, is ill conditioned (nearly repeated
  roots of eq. (4): :func:`impactdamper.core.linear.scaled_condition`), where the reference
  uses the matrix exponential;
* parameters outside the native scales (the reference rescales them);
* an error of the kernels that is not a work bound (a failed search, a resonance in contact):
  the reference is re-run so that its exception, with its message, is raised.

A run that reaches the work bound (the reference's step budget, more than
``MAX_EVENTS_AT_ONE_TIME`` events at one instant) raises the reference's error with the
reference's message, worded from the kernels' diagnostics.

The maximum excursion x1_max is refined by golden-section search where the reference uses
scipy's bounded Brent search; both stop at 1e-12 T, and the maximum's value differs by the
square of that (far below 1e-12 x_st).

The modules, each one idea:

* :mod:`~impactdamper.core.compiled.layout` -- the codes and indices the kernels share;
* :mod:`~impactdamper.core.compiled.pack` -- a parameter set packed into arrays;
* :mod:`~impactdamper.core.compiled.modal` -- each mode's and functional's arrays in it (one set
  compiled, a stack with numpy);
* :mod:`~impactdamper.core.compiled.flow` -- the exact flow between events;
* :mod:`~impactdamper.core.compiled.march` -- the certified event march and its polish;
* :mod:`~impactdamper.core.compiled.loop` -- the event loop, the impact law, the modes, the
  work bound and the recorded run;
* :mod:`~impactdamper.core.compiled.settle` -- the settled motion (the period loop and the
  describing run), one point or a row of them;
* :mod:`~impactdamper.core.compiled.periodicity` -- the period test on the stroboscopic sections;
* :mod:`~impactdamper.core.compiled.settled_cycle` -- the settled cycle described (regime, impacts,
  contact fraction, the section handed on);
* :mod:`~impactdamper.core.compiled.excursion` -- the cycle's largest excursion x1_max;
* :mod:`~impactdamper.core.compiled.tangent` -- the Lyapunov tangent walk on the event loop
  (transition and saltation matrices, QR per event and period);
* :mod:`~impactdamper.core.compiled.backend` -- the backend object (:data:`COMPILED`) that the
  registry (:mod:`impactdamper.core.backends`) hands out: the only entry point;
* :mod:`~impactdamper.core.compiled.cache` -- numba's cache kept in step with the sources.
"""

from __future__ import annotations

from impactdamper.core.compiled.cache import keep_in_step

keep_in_step()  # before any kernel is loaded from numba's cache (see cache.py); the imports follow it

from impactdamper.core.compiled.backend import COMPILED, CompiledBackend  # noqa: E402

__all__ = ["COMPILED", "CompiledBackend"]
