"""Parameters of the two-mass impact suppressor in the paper's relative form.

Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100,
section "The results of the calculations": the system is described by

    mu = m2/m1, theta = omega/omega1, N = omega2/omega1,
    delta1 = k1/(2 m1 omega1), delta2 = k2/(2 m2 omega1), x_st = P0/c1,

with omega1 = sqrt(c1/m1), omega2 = sqrt(c2/m2), the restitution coefficient R and the
initial gap Delta0, given here relative to the static deflection as ``gap = Delta0/x_st``.

The paper gives only relative values; the object's mass ``m1`` is a free scale. Results in
relative coordinates (x1/x_st, (x2 - Delta0)/x_st, t/T) do not depend on it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

__all__ = ["Parameters", "REFERENCE"]


def _check(name: str, value: float, ok: bool, allowed: str) -> None:
    if not ok:
        raise ValueError(f"`{name}` = {value!r} is not allowed: must be {allowed}")


@dataclass(frozen=True)
class Parameters:
    """Relative parameters of the suppressor; defaults are the paper's reference case (Fig. 2).

    Parameters
    ----------
    theta : float
        Forcing frequency over the object's natural frequency, omega/omega1 (> 0).
    mu : float
        Mass ratio m2/m1 (> 0).
    N : float
        Suppressor's partial frequency over the object's, omega2/omega1 (> 0).
    delta1, delta2 : float
        Relative damping k1/(2 m1 omega1) and k2/(2 m2 omega1) (>= 0).
    R : float
        Newton's coefficient of restitution, in [0, 1].
    gap : float
        Initial gap Delta0/x_st (any finite value; negative means preloaded contact).
    omega : float
        Forcing frequency in rad/s (> 0); T = 2 pi/omega.
    x_st : float
        Static deflection P0/c1 in m (> 0).
    m1 : float
        Mass of the object in kg (> 0): a free scale, default 1.
    """

    theta: float = 1.0
    mu: float = 0.08
    N: float = 0.5
    delta1: float = 0.05
    delta2: float = 0.05
    R: float = 0.7
    gap: float = -5.8
    omega: float = 10.0
    x_st: float = 1.0
    m1: float = 1.0

    # Derived dimensional quantities, filled in by __post_init__.
    omega1: float = field(init=False, repr=False, compare=False)
    omega2: float = field(init=False, repr=False, compare=False)
    m2: float = field(init=False, repr=False, compare=False)
    c1: float = field(init=False, repr=False, compare=False)
    c2: float = field(init=False, repr=False, compare=False)
    k1: float = field(init=False, repr=False, compare=False)
    k2: float = field(init=False, repr=False, compare=False)
    P0: float = field(init=False, repr=False, compare=False)
    Delta0: float = field(init=False, repr=False, compare=False)
    T: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("theta", "mu", "N", "delta1", "delta2", "R", "gap", "omega", "x_st", "m1"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"`{name}` = {value!r} is not allowed: must be a real number")
            _check(name, value, math.isfinite(value), "a finite number")
        for name in ("theta", "mu", "N", "omega", "x_st", "m1"):
            _check(name, getattr(self, name), getattr(self, name) > 0, "> 0")
        for name in ("delta1", "delta2"):
            _check(name, getattr(self, name), getattr(self, name) >= 0, ">= 0")
        _check("R", self.R, 0.0 <= self.R <= 1.0, "in [0, 1]")

        omega1 = self.omega / self.theta
        omega2 = self.N * omega1
        m2 = self.mu * self.m1
        # Squares as products: float ``**`` raises OverflowError where ``*`` gives inf, which
        # the check below turns into the one-line ValueError (helper fix, e.g. theta=1e-300).
        derived = {
            "omega1": omega1,
            "omega2": omega2,
            "m2": m2,
            "c1": self.m1 * (omega1 * omega1),
            "c2": m2 * (omega2 * omega2),
            "k1": 2.0 * self.m1 * omega1 * self.delta1,
            "k2": 2.0 * m2 * omega1 * self.delta2,
            "P0": self.m1 * (omega1 * omega1) * self.x_st,
            "Delta0": self.gap * self.x_st,
            "T": 2.0 * math.pi / self.omega,
        }
        for name, value in derived.items():
            object.__setattr__(self, name, float(value))
            # Extreme but valid inputs can still overflow the dimensional values.
            _check(name, value, math.isfinite(value) and (value != 0.0 or name in ("k1", "k2", "Delta0")),
                   "finite and non-zero: the relative parameters overflow it")

    @property
    def h1(self) -> float:
        """Attenuation coefficient k1/(2 m1) in 1/s (eq. 5)."""
        return self.k1 / (2.0 * self.m1)

    @property
    def h2(self) -> float:
        """Attenuation coefficient k2/(2 m2) in 1/s (eq. 5)."""
        return self.k2 / (2.0 * self.m2)

    @property
    def reduced_mass(self) -> float:
        """m1 m2/(m1 + m2), the mass of the relative motion (eq. 14)."""
        return self.m1 * self.m2 / (self.m1 + self.m2)

    def replace(self, **changes: float) -> "Parameters":
        """A copy with some relative parameters changed (validated like the constructor)."""
        unknown = set(changes) - set(self.names())
        if unknown:
            name = sorted(unknown)[0]
            raise ValueError(f"`{name}` is not a parameter: allowed are {', '.join(self.names())}")
        return dataclasses.replace(self, **changes)

    @staticmethod
    def names() -> tuple[str, ...]:
        """The relative parameters a user sets, in the paper's order."""
        return ("theta", "mu", "N", "delta1", "delta2", "R", "gap", "omega", "x_st", "m1")

    def to_dict(self) -> dict[str, float]:
        """The relative parameters as a plain dict (JSON-ready)."""
        return {name: float(getattr(self, name)) for name in self.names()}


REFERENCE = Parameters()
"""The paper's reference case of Fig. 2."""
