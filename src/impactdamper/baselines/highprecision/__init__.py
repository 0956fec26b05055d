"""High-precision reference: the same closed form in arbitrary precision (mpmath).

The double-precision library (Algorithm No. 2 of Timofeev et al. 2019 with the exact flow,
and the closed-form Algorithm No. 1) is accurate to about 1e-14 in impact phase. To measure
errors that small, this module recomputes the reference case's motion at ``DIGITS``
significant digits with the same closed form but independent code:

* the free mode's state matrix (eqs. 2, 9) in mpmath, its free response by eigen-decomposition
  (``mpmath.eig``; the matrix exponential ``mpmath.expm`` where the eigenvectors are
  ill-conditioned), the forced response by complex amplitudes, (i omega I - M) Yhat = b
  (eq. 10 in state form);
* the impact law of eqs. (14), (21)-(22);
* the next impact as the first root of the gap (eq. 20), found by ``mpmath.findroot`` on a
  bracket around the double-precision estimate, and *certified independently* of the
  library's event search: on every interval [u, v] before the bracket the gap g satisfies
  min(g(u), g(v)) > K (v - u)^2 / 8 with K a bound of |g''| (then g > 0 on [u, v], because a
  function with |g''| <= K lies above its chord minus K h^2 / 8); intervals that fail are
  halved. Inside the bracket, |g'(mid)| > K (v - u) / 2 proves g monotone, so the root is
  unique. Without an estimate the same scan finds the bracket itself.

For |g''| the modal form gives K = |G| omega^2 + sum_j |g_j| |lambda_j|^2 (all Re lambda_j
<= 0), with G the forced and g_j the modal amplitudes of the gap; with the matrix exponential
the free response's energy, which never grows, bounds it (as in ``events.py``, but evaluated
here in mpmath).

Two settled-cycle computations check each other: the paper's Algorithm No. 1 (eqs. 4-8,
10-17) in mpmath, with the roots of eq. (4) from ``mpmath.polyroots``, and a Newton solve of
the impact-to-impact map of Algorithm No. 2 (flow over one period, then the impact law) for
its fixed point, started from Algorithm No. 1's orbit and certified to have no impact inside
the period.

Everything is computed from the double-precision values of the relative parameters taken as
exact binary numbers, so the double and the mpmath computations solve the same problem.

The model, its exact motion and the certified impacts are in :mod:`.model`; Algorithm No. 1,
the settled cycle and the closed-form amplitudes in :mod:`.cycle`.
"""

from impactdamper.baselines.highprecision.cycle import (
    MPAlgorithm1,
    MPCycle,
    algorithm1_mp,
    forced_amplitudes_mp,
    settled_cycle,
)
from impactdamper.baselines.highprecision.model import (
    DIGITS,
    HighPrecisionError,
    MPImpact,
    MPModel,
    default_initial_state_mp,
    first_impacts,
    gap_minimum,
    to_float,
)

__all__ = [
    "DIGITS",
    "HighPrecisionError",
    "MPModel",
    "MPImpact",
    "MPCycle",
    "MPAlgorithm1",
    "first_impacts",
    "settled_cycle",
    "algorithm1_mp",
    "default_initial_state_mp",
    "gap_minimum",
    "forced_amplitudes_mp",
    "to_float",
]
