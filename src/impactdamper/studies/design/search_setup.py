"""What the design search is asked, and within which boxes: the object's inputs checked, the
boxes derived from the object, the searches' budgets, and both read from the workflow's config
(the call itself: :func:`impactdamper.studies.design.optimum.design_optima`).

The boxes are derived from the object (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100, eqs. 1-2 and 9-10 in relative form): with s_T the stroke of
its optimal TMD,

* the impact suppressor's gap Delta0/x_st in [-s_T, 1.5 s_T] (a stop preloaded by the TMD's
  own travel to one beyond it: there the device is a TMD that never reaches its stop, the
  *TMD limit*), and, *with its stop within reach*, in [-s_T, s_T];
* N in [N_LOW, N_HIGH] times Den Hartog's 1/(1 + mu); delta2 in [0, DELTA2_HIGH times his
  sqrt(3 mu/(8 (1 + mu)^3))] (the TMD's delta2 from DELTA2_LOW of that); R in [0.2, 0.95]
  (a polymer pad to hardened steel);
* under the stroke limit S (default STROKE_FRACTION of the optimal TMD's stroke) the impact
  suppressor's gap at most S (its travel towards the stop is the gap); the TMD's delta2 up to a
  locked absorber (:mod:`~impactdamper.studies.design.tmd`), so that a box bound never decides
  whether a TMD can keep the limit.
"""

from __future__ import annotations

import dataclasses

from impactdamper.analysis.linear_device import check_band, den_hartog
from impactdamper.core.validation import finite_argument
from impactdamper.studies.design.devices import IMPACT_NAMES, RANGES, Uncertainty
from impactdamper.studies.design.search import Budget

__all__ = [
    "BUDGET",
    "ROBUST_BUDGET",
    "STROKE_FRACTION",
    "check_object",
    "design_bounds",
    "design_options",
]

# The search's budget, the same for both devices and every criterion (what a minute on two
# cores buys: see the design benchmark).
BUDGET = Budget(
    samples=128, starts=2, polls=10, first_step=1 / 8, last_step=1 / 128, coarse_above=1 / 32, polish=30, checks=6
)
# The robust and travel-limited searches' budget: the nominal one, their global stage one
# shared sample of the whole box evaluated under every robust criterion's scenarios.
ROBUST_BUDGET = BUDGET
# The box's sides relative to Den Hartog's optimum (module docstring).
N_LOW, N_HIGH = 0.2, 1.5
DELTA2_LOW, DELTA2_HIGH = 0.01, 3.0
R_BOX = (0.2, 0.95)
GAP_FULL = 1.5
# The stroke limit of the stroke-limited rows, by default: this fraction of the optimal TMD's.
STROKE_FRACTION = 0.7


def _in_range(name: str, value: object, unit: str = "") -> float:
    lo, hi = RANGES[name]
    v = finite_argument(name, value)
    if not lo <= v <= hi:
        raise ValueError(f"`{name}` = {v!r} is not allowed: must be in [{lo:g}, {hi:g}]{unit}")
    return v


def check_object(band, mu, delta1, uncertainty: Uncertainty, max_stroke, stop_stiffness, natural_frequency) -> tuple:
    """The command's inputs within :data:`RANGES` (one-line errors naming the input and its
    range). Returns (band, mu, delta1)."""
    try:
        a, b = band
    except (TypeError, ValueError):
        raise ValueError(f"`band` = {band!r} is not allowed: must be (theta_start, theta_stop)") from None
    a, b = _in_range("theta_start", a), _in_range("theta_stop", b)
    if not RANGES["band_width"][0] <= b - a <= RANGES["band_width"][1]:
        lo, hi = RANGES["band_width"]
        raise ValueError(
            f"`theta_stop` = {b!r} is not allowed: the band theta_stop - theta_start must be in [{lo:g}, {hi:g}] "
            f"(theta_start = {a!r})"
        )
    mu, delta1 = _in_range("mu", mu), _in_range("delta1", delta1)
    _in_range("detuning", uncertainty.detuning)
    _in_range("force_low", uncertainty.force[0])
    _in_range("force_high", uncertainty.force[1])
    _in_range("restitution_drift", uncertainty.restitution)
    _in_range("stiffness_drift", uncertainty.stiffness)
    _in_range("damping_drift", uncertainty.damping)
    _in_range("stop_stiffness", stop_stiffness, " (times the object's spring c1)")
    _in_range("natural_frequency", natural_frequency, " Hz")
    if max_stroke is not None:
        s = finite_argument("max_stroke", max_stroke)
        if not s > 0:
            raise ValueError(f"`max_stroke` = {s!r} is not allowed: must be > 0 (x_st)")
    return check_band((a, b)), mu, delta1


def design_bounds(mu: float, tmd_stroke: float) -> dict:
    """The boxes of the search (module docstring): ``tmd``, ``impact`` (the whole box) and
    ``impact_reach`` (the stop within reach), from the object's mass ratio and its optimal TMD's
    stroke."""
    dh = den_hartog(mu)
    n_dh, d_dh = dh["N"], dh["delta2"]
    N = (N_LOW * n_dh, N_HIGH * n_dh)
    impact = dict(zip(IMPACT_NAMES, ((-tmd_stroke, GAP_FULL * tmd_stroke), N, (0.0, DELTA2_HIGH * d_dh), R_BOX)))
    return {
        "tmd": {"N": N, "delta2": (DELTA2_LOW * d_dh, DELTA2_HIGH * d_dh)},
        "impact": impact,
        "impact_reach": {**impact, "gap": (-tmd_stroke, tmd_stroke)},
    }


def design_options(design: dict) -> dict:
    """:func:`~impactdamper.studies.design.optimum.design_optima`'s options from the config's
    ``design`` section: the uncertainties (``detuning``, ``force_band``, ``restitution_drift``)
    and the budgets (``search_samples``, ``search_starts``, ``search_polls``, ``search_polish``,
    ``robust_polls``, ``robust_polish``, ``search_checks``; the steps are :data:`BUDGET`'s).
    With the shipped config they are the command's defaults, so that the design table is what ``design --json`` prints."""
    budget = dataclasses.replace(
        BUDGET,
        samples=int(design["search_samples"]),
        starts=int(design["search_starts"]),
        polls=int(design["search_polls"]),
        polish=int(design["search_polish"]),
        checks=int(design["search_checks"]),
    )
    robust = dataclasses.replace(
        budget,
        polls=int(design["robust_polls"]),
        polish=int(design["robust_polish"]),
        checks=int(design["search_checks"]),
    )
    low, high = (float(x) for x in design["force_band"])
    unc = Uncertainty(
        float(design["detuning"]),
        (low, high),
        float(design["restitution_drift"]),
        float(design.get("stiffness_drift", Uncertainty.stiffness)),
        float(design.get("damping_drift", Uncertainty.damping)),
    )
    return {"uncertainty": unc, "budget": budget, "robust_budget": robust}
