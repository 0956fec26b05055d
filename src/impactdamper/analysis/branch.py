"""A branch of periodic impacting cycles in one parameter: its points and its special points.

What :func:`impactdamper.analysis.continuation.continue_orbit` returns (a :class:`Branch` of
:class:`BranchPoint` orbits of Timofeev et al. (2019)'s two-mass system, solved by the Newton
shooting of the impact law of eqs. 21-22 and the exact flow of eq. 18, with its
:class:`SpecialPoint` bifurcations and grazings located), and how an orbit becomes a point.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.analysis.cycle import PeriodicOrbit
from impactdamper.core.parameters import ScaleMap

__all__ = ["Branch", "BranchPoint", "SpecialPoint", "SPECIAL_KINDS", "branch_point", "rescale_branch"]

# Kinds of special point a branch reports (see SpecialPoint).
SPECIAL_KINDS = ("fold", "period_doubling", "neimark_sacker", "grazing_velocity", "grazing_interior")


@dataclass(frozen=True)
class BranchPoint:
    """One orbit on a branch.

    Attributes
    ----------
    value : float
        The continuation parameter's value.
    phases : tuple of float
        Impact times over T modulo 1, in cycle order.
    t_over_T : tuple of float
        Impact times since the cycle's first impact, over T.
    velocities : tuple of float
        Closing velocities over x_st omega.
    multipliers : tuple of complex
        Floquet multipliers, largest modulus first.
    stable, admissible : bool
    min_gap : float
        Smallest interior gap minimum over x_st (inf if none).
    x1_max : float
        max |x1|/x_st over the cycle.
    times : tuple of float
        Absolute impact times, s (first in [0, T)).
    states_after : tuple of tuple
        (x1, x2, x1', x2') just after each impact: with ``times``, a seed for
        :func:`orbit_from_cycle` or a start for the simulation.
    """

    value: float
    phases: tuple
    t_over_T: tuple
    velocities: tuple
    multipliers: tuple
    stable: bool
    admissible: bool
    min_gap: float
    x1_max: float
    times: tuple = field(default=(), repr=False)
    states_after: tuple = field(default=(), repr=False)

    def to_dict(self) -> dict:
        return {
            "value": self.value,
            "phases": list(self.phases),
            "t_over_T": list(self.t_over_T),
            "velocities_rel": list(self.velocities),
            "multipliers": [abs(m) for m in self.multipliers],
            "multipliers_complex": [[m.real, m.imag] for m in self.multipliers],
            "stable": self.stable,
            "admissible": self.admissible,
            "min_gap": self.min_gap if math.isfinite(self.min_gap) else None,
            "x1_max": self.x1_max,
            "times": list(self.times),
            "states_after": [list(y) for y in self.states_after],
        }


@dataclass(frozen=True)
class SpecialPoint:
    """A located bifurcation or grazing on a branch.

    Attributes
    ----------
    kind : str
        One of ``fold`` (turning point, a multiplier at +1), ``period_doubling`` (a multiplier
        at -1), ``neimark_sacker`` (a complex pair on the unit circle), ``grazing_velocity`` (an
        impact's closing velocity reaches zero: the impact disappears), ``grazing_interior``
        (the gap's interior minimum reaches zero: a new impact appears).
    value : float
        Parameter value where it happens.
    index : int
        It lies between branch points ``index - 1`` and ``index``.
    point : BranchPoint
        The orbit there.
    detail : str
        What changes (e.g. which impact, the impact sequence before and after).
    """

    kind: str
    value: float
    index: int
    point: BranchPoint
    detail: str

    def to_dict(self) -> dict:
        return {**_fields(self, "kind", "value", "index", "detail"), "point": self.point.to_dict()}


@dataclass(frozen=True)
class Branch:
    """A followed branch of z-impact cycles of period k T.

    Attributes
    ----------
    parameter : str
        Name of the continuation parameter (a field of :class:`Parameters`).
    period_multiple, impacts_per_cycle : int
        k and z (Peterka's z/k label).
    points : tuple of BranchPoint
    special : tuple of SpecialPoint
        Detected folds, period doublings, Neimark-Sacker points and grazings, in order.
    end_reason : str
        Why the branch ends: ``bound`` (the parameter range's end), ``grazing_velocity`` or
        ``grazing_interior`` (the impact sequence changes there), ``newton_failure``,
        ``max_points``.
    end_value : float
        The parameter where it ends.
    """

    parameter: str
    period_multiple: int
    impacts_per_cycle: int
    points: tuple
    special: tuple
    end_reason: str
    end_value: float

    @property
    def values(self) -> np.ndarray:
        return np.array([q.value for q in self.points])

    def to_dict(self) -> dict:
        return {
            **_fields(self, "parameter", "period_multiple", "impacts_per_cycle", "end_reason", "end_value"),
            "special": [s.to_dict() for s in self.special],
            "points": [q.to_dict() for q in self.points],
        }


def _fields(obj, *names: str) -> dict:
    """The named fields of ``obj`` as a dict, in that order (a JSON object's plain keys)."""
    return {name: getattr(obj, name) for name in names}


def branch_point(value: float, o: PeriodicOrbit) -> BranchPoint:
    """The branch point of a solved orbit at the parameter value ``value``."""
    return BranchPoint(
        value=float(value),
        phases=tuple(i.phase for i in o.impacts),
        t_over_T=tuple(i.t_over_T for i in o.impacts),
        velocities=tuple(i.velocity / (o.p.x_st * o.p.omega) for i in o.impacts),
        multipliers=tuple(complex(m) for m in o.multipliers),
        stable=bool(o.stable),
        admissible=bool(o.admissible),
        min_gap=float(o.min_gap),
        x1_max=float(o.x1_max),
        times=tuple(float(t) for t in o.times),
        states_after=tuple(tuple(float(v) for v in y) for y in o.states_after),
    )


def rescale_branch(branch: Branch, scales: ScaleMap) -> Branch:
    """A branch's impact times and states in ``scales.target``'s units (all else is relative)."""

    def point(q: BranchPoint) -> BranchPoint:
        return dataclasses.replace(
            q,
            times=tuple(scales.apply(t, "time") for t in q.times),
            states_after=tuple(tuple(float(v) for v in scales.full(np.array(y))) for y in q.states_after),
        )

    return dataclasses.replace(
        branch,
        points=tuple(point(q) for q in branch.points),
        special=tuple(dataclasses.replace(sp, point=point(sp.point)) for sp in branch.special),
    )
