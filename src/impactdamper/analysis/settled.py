"""The settled motion at one point: the names of its two questions, kept here for old imports.

:func:`solve_point` answers "the settled motion at this sweep point, continuing its
neighbour's" (the cheapest-first ladder, :mod:`impactdamper.analysis.ladder`; its settings,
result and labels in :mod:`impactdamper.analysis.point`; the Newton rescue of a run that did not
settle in :mod:`impactdamper.analysis.rescue`). :func:`steady_state_auto` answers "the settled
motion at these parameters" and is a deprecated alias of
``impactdamper.steady_state(p, attractor=True)`` (:mod:`impactdamper.analysis.solve`).
"""

from __future__ import annotations

from impactdamper.analysis.ladder import CLOSED_FORM_MARGIN, carry_state, solve_point
from impactdamper.analysis.point import (
    FAILED,
    LABELS_ORDER,
    STABILITY_MARGIN,
    SweepPoint,
    SweepSettings,
    label_of,
)
from impactdamper.analysis.rescue import RESCUE_MAX_K, RESCUE_MISMATCH, rescue_from_sections
from impactdamper.analysis.solve import STEADY_KEYWORDS, steady_state_auto

__all__ = [
    "rescue_from_sections",
    "SweepSettings",
    "SweepPoint",
    "FAILED",
    "LABELS_ORDER",
    "label_of",
    "carry_state",
    "solve_point",
    "steady_state_auto",
    "STEADY_KEYWORDS",
    "RESCUE_MISMATCH",
    "RESCUE_MAX_K",
    "STABILITY_MARGIN",
    "CLOSED_FORM_MARGIN",
]
