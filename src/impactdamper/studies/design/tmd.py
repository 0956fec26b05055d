"""The linear TMD's optimum converged: the global search's answer refined by nested Brent
minimisations on the exact peaks, its box widened where it binds.

The TMD's criteria are exact functions of (N, delta2): its peak over a band is the largest real
stationary point of a rational function (:func:`impactdamper.analysis.linear_device.linear_maxima`),
its worst peak over the detuned scenarios the largest of three such, its band average a
quadrature on the band grid. The global search
(:func:`impactdamper.studies.design.search.search`, the impact device's budget) finds the basin;
it stops at its last compass step, 1/128 of the box's side, about 1e-4 above the optimum. Here
it is refined: for each N the criterion is minimised over log(delta2) by bounded Brent, and that
minimum over N by bounded Brent again (a max of smooth peaks is minimised at its kink, where two
peaks are equal: the equal-peak optimum; a golden-section bracket converges to it as it does to a
smooth minimum), both to ``XTOL`` relative, so the value is converged to far below 1e-6
relative. The brackets reach a factor BRACKET around the search's answer; where the answer lies
at a bracket's end it is re-centred there (at most WIDENINGS times). delta2 may grow to
DELTA2_LOCKED times Den Hartog's (the absorber locked to the object): the box of the search binds
only there, and N only at the search box's own bounds, which the record then names.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.optimize

from impactdamper.analysis.linear_device import LinearDevice
from impactdamper.studies.design.search import SearchResult, _Counter, _checked, at_bound

__all__ = ["refine_tmd", "equal_peaks", "XTOL", "BRACKET", "DELTA2_LOCKED"]

# Relative tolerance of each Brent minimisation in its variable (log delta2, N).
XTOL = 1e-10
# The brackets around the search's answer: a factor of this either way (log delta2) and of its
# square root (N).
BRACKET = 4.0
WIDENINGS = 4
# delta2 at most this times Den Hartog's: beyond it the absorber moves with the object (locked).
DELTA2_LOCKED = 1000.0


def _brent(fun, lo: float, hi: float) -> tuple[float, float]:
    res = scipy.optimize.minimize_scalar(
        fun, bounds=(lo, hi), method="bounded", options={"xatol": XTOL * max(abs(lo), abs(hi), 1.0), "maxiter": 500}
    )
    return float(res.x), float(res.fun)


def refine_tmd(crit, result: SearchResult, bounds: dict, d_dh: float, budget) -> SearchResult:
    """The TMD search's ``result`` refined (module docstring) over ``bounds`` widened in delta2
    to DELTA2_LOCKED x ``d_dh``; the answer is the better of the two, with the 2 % check of
    :func:`~impactdamper.studies.design.search.search` over the widened box and its evaluations
    (``refine``: the criterion's evaluations of the refinement)."""
    wide = {"N": tuple(bounds["N"]), "delta2": (bounds["delta2"][0], DELTA2_LOCKED * d_dh)}
    f = _Counter(crit, ["N", "delta2"])
    count = [0]

    def value(N: float, d2: float) -> float:
        count[0] += 1
        return float(f(np.array([[N, d2]]), "final")[0])

    n_lo, n_hi = wide["N"]
    l_lo, l_hi = math.log(wide["delta2"][0]), math.log(wide["delta2"][1])

    def inner(N: float, centre: float) -> tuple[float, float]:
        lo, hi = max(l_lo, centre - math.log(BRACKET)), min(l_hi, centre + math.log(BRACKET))
        for _ in range(WIDENINGS + 1):
            t, v = _brent(lambda s: value(N, math.exp(s)), lo, hi)
            end = min(t - lo, hi - t) <= 1e-6 * (hi - lo)
            if not end or (t - lo <= 1e-6 * (hi - lo) and lo <= l_lo) or (hi - t <= 1e-6 * (hi - lo) and hi >= l_hi):
                break
            lo, hi = max(l_lo, t - math.log(BRACKET)), min(l_hi, t + math.log(BRACKET))
        return t, v

    N0, d0 = result.x["N"], result.x["delta2"]
    centre = [math.log(max(d0, wide["delta2"][0]))]

    def outer(N: float) -> float:
        t, v = inner(N, centre[0])
        return v

    lo, hi = max(n_lo, N0 / math.sqrt(BRACKET)), min(n_hi, N0 * math.sqrt(BRACKET))
    for _ in range(WIDENINGS + 1):
        N, _ = _brent(outer, lo, hi)
        if min(N - lo, hi - N) > 1e-6 * (hi - lo) or lo <= n_lo or hi >= n_hi:
            break
        lo, hi = max(n_lo, N / math.sqrt(BRACKET)), min(n_hi, N * math.sqrt(BRACKET))
    t, v = inner(N, centre[0])
    x = {"N": N, "delta2": math.exp(t)}
    if not v < result.value:
        x = dict(result.x)
    # The 2 % check in a box whose side is the search's (its smallest move is a tenth of 2 % of
    # the side: the widened side would make it coarse), delta2 free above to twice the answer.
    near = {
        "N": wide["N"],
        "delta2": (wide["delta2"][0], min(wide["delta2"][1], max(bounds["delta2"][1], 2 * x["delta2"]))),
    }
    x, v, check = _checked(f, x, near, budget, lambda m: None)
    evaluations = {**result.evaluations, "refine": count[0]}
    # At a bound: of the search's N box, or delta2 near the locked absorber (judged on the check's
    # box: a fraction of the widened side would flag any delta2 near its lower end).
    flags = set(at_bound(x, near)) | {n for n in wide if None in (check[n]["down"], check[n]["up"])}
    return SearchResult(x, v, evaluations, tuple(n for n in wide if n in flags), check, wide, "refined", result.starts)


def equal_peaks(mu: float, delta1: float, x: dict, band: tuple) -> dict:
    """The two highest local maxima of the TMD ``x``'s |x1|/x_st over ``band`` and their
    relative difference (0 at an equal-peak optimum; None with a single maximum)."""
    dev = LinearDevice(mu, x["N"], delta1, x["delta2"])
    num, den, _ = dev.polynomials()
    from impactdamper.analysis.linear_device import linear_maxima

    peaks = linear_maxima(num, den, band)[:2]
    out = {"peaks": [{"theta": t, "value": v} for t, v in peaks]}
    out["relative_difference"] = (peaks[0][1] - peaks[1][1]) / peaks[0][1] if len(peaks) > 1 else None
    return out
