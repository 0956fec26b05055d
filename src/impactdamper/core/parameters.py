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

# The generic argument checks live in arguments.py (validation.py, the module to import a check
# from, gathers them with the solver's); the parameters check their own values with them.
from impactdamper.core.arguments import ArgumentTypeError, check_value, finite_argument, show_value

__all__ = [
    "Parameters",
    "REFERENCE",
    "ArgumentTypeError",
    "PARAMETER_TABLE",
    "LINEAR_PARAMETERS",
    "RELATIVE_PARAMETERS",
    "state_scale",
]


def require_parameters(p: object, name: str = "p") -> Parameters:
    """``p`` if it is a :class:`Parameters`, else an :class:`ArgumentTypeError` naming ``name``."""
    if not isinstance(p, Parameters):
        raise ArgumentTypeError(
            f"`{name}` = {show_value(p)} is not allowed: must be a Parameters (e.g. impactdamper.Parameters(gap=-9.6))"
        )
    return p


# The dimensional values derived from the relative parameters: how (for messages) and from which.
_DERIVED = {
    "omega1": ("omega/theta", ("omega", "theta")),
    "omega2": ("N omega/theta", ("N", "omega", "theta")),
    "m2": ("mu m1", ("mu", "m1")),
    "c1": ("m1 (omega/theta)^2", ("m1", "omega", "theta")),
    "c2": ("mu m1 (N omega/theta)^2", ("mu", "m1", "N", "omega", "theta")),
    "k1": ("2 m1 omega delta1/theta", ("delta1", "m1", "omega", "theta")),
    "k2": ("2 mu m1 omega delta2/theta", ("delta2", "mu", "m1", "omega", "theta")),
    "P0": ("m1 (omega/theta)^2 x_st", ("m1", "omega", "theta", "x_st")),
    "Delta0": ("gap x_st", ("gap", "x_st")),
    "T": ("2 pi/omega", ("omega",)),
    # The units results are reported in (velocities, pulses): they must exist too.
    "x_st omega": ("x_st omega", ("x_st", "omega")),
    "m1 x_st omega": ("m1 x_st omega", ("m1", "x_st", "omega")),
}


@dataclass(frozen=True)
class _ParameterSpec:
    """One parameter a user sets (a field of :class:`Parameters`), as the package reads it by
    name: its range, the value a message measures extremes against, its role and its help.

    Attributes
    ----------
    name : str
        The field of :class:`Parameters` (the config key, the CLI flag ``--name``, the column
        of the compiled kernels' packed values).
    allowed : str
        Its range: ``"> 0"``, ``">= 0"``, ``"in [0, 1]"``, or ``""`` (any finite value).
    typical : float
        Its magnitude in the reference case: a message about a numerical limit names the
        parameter farthest from it in decades (:func:`most_extreme`).
    role : str
        ``"linear"``: the linear part (masses, stiffnesses, dampings, forcing; eqs. 1-11);
        ``"impact"``: the impact law and the stop (eqs. 14, 20-22); ``"scale"``: a free scale
        (results in relative units do not depend on it).
    help : str
        One line for the command line's ``--help``.
    symbol : str
        Its symbol in TeX math (no dollars): ``\\theta``, ``\\Delta_0/x_{\\mathrm{st}}``; the
        report's tables and lists, the figures' labels.
    macro : str
        Its part of a TeX macro name (letters only): ``Theta``, ``DeltaOne`` (``\\StatedTheta``,
        ``\\NearestMaxDeltaOne``).
    plain : str
        Its name in plain text (the README): ``theta``, ``Delta0/x_st``.
    label : str
        Its axis label in a figure (TeX text, math in dollars): ``$\\mu = m_2/m_1$``.
    long_label : str
        Its axis label where a figure has room to name it in words: ``initial gap
        $\\Delta_0/x_{\\mathrm{st}}$`` (by default, ``label``: it names it already).
    """

    name: str
    allowed: str
    typical: float
    role: str
    help: str
    symbol: str
    macro: str
    plain: str
    label: str
    long_label: str = ""

    def __post_init__(self) -> None:
        if not self.long_label:
            object.__setattr__(self, "long_label", self.label)

    def ok(self, value: float) -> bool:
        """Whether ``value`` (finite) is in the parameter's range."""
        return _IN_RANGE[self.allowed](value)


_IN_RANGE = {
    "> 0": lambda v: v > 0,
    ">= 0": lambda v: v >= 0,
    "in [0, 1]": lambda v: 0.0 <= v <= 1.0,
    "": lambda v: True,
}
# The one table of the parameters, in the paper's order: Parameters.names(), the ranges checked
# on construction, the compiled kernels' packed columns (compiled/pack.py reads them by name),
# the CSV columns, the command line's flags and their help, the sets of parameters a message
# may name (LINEAR_PARAMETERS, RELATIVE_PARAMETERS) and every display of a parameter (symbols,
# macro names, plain names, axis labels: studies/vocabulary.py) derive from it. A new parameter is
# a row here and a field of Parameters (tests/unit/test_parameters.py holds the two together).
# fmt: off
PARAMETER_TABLE = (
    # name, range, typical value, role, help; then its symbol, macro-name part, plain name, axis
    # label (and a longer one, where it differs).
    _ParameterSpec("theta", "> 0", 1.0, "linear", "forcing frequency ratio omega/omega1",
                  "\\theta", "Theta", "theta", "$\\theta = \\omega/\\omega_1$",
                  "frequency ratio $\\theta = \\omega/\\omega_1$"),
    _ParameterSpec("mu", "> 0", 0.08, "linear", "mass ratio m2/m1",
                  "\\mu", "Mu", "mu", "$\\mu = m_2/m_1$"),
    _ParameterSpec("N", "> 0", 0.5, "linear", "frequency ratio omega2/omega1",
                  "N", "N", "N", "$N = \\omega_2/\\omega_1$"),
    _ParameterSpec("delta1", ">= 0", 0.05, "linear", "relative damping k1/(2 m1 omega1)",
                  "\\delta_1", "DeltaOne", "delta1", "$\\delta_1$ (object's damping)"),
    _ParameterSpec("delta2", ">= 0", 0.05, "linear", "relative damping k2/(2 m2 omega1)",
                  "\\delta_2", "DeltaTwo", "delta2", "$\\delta_2$ (suppressor's damping)"),
    _ParameterSpec("R", "in [0, 1]", 0.7, "impact", "coefficient of restitution, in [0, 1]",
                  "R", "R", "R", "restitution $R$"),
    _ParameterSpec("gap", "", 5.8, "impact", "initial gap Delta0/x_st",
                  "\\Delta_0/x_{\\mathrm{st}}", "Gap", "Delta0/x_st", "$\\Delta_0/x_{\\mathrm{st}}$",
                  "initial gap $\\Delta_0/x_{\\mathrm{st}}$"),
    _ParameterSpec("omega", "> 0", 10.0, "scale", "forcing frequency, rad/s",
                  "\\omega", "Omega", "omega", "forcing frequency $\\omega$, rad/s"),
    _ParameterSpec("x_st", "> 0", 1.0, "scale", "static deflection P0/c1, m",
                  "x_{\\mathrm{st}}", "Xst", "x_st", "static deflection $x_{\\mathrm{st}}$, m"),
    _ParameterSpec("m1", "> 0", 1.0, "scale", "object mass, kg (a free scale)",
                  "m_1", "MOne", "m1", "object mass $m_1$, kg"),
)
# fmt: on
# The parameters of the linear part (the model's matrices depend on these only) and all the
# relative ones (the free scales left out): the candidates a message about the matrices, and
# about a solver's limits, may name.
LINEAR_PARAMETERS = tuple(s.name for s in PARAMETER_TABLE if s.role == "linear")
RELATIVE_PARAMETERS = tuple(s.name for s in PARAMETER_TABLE if s.role != "scale")
# Values of the reference case, against which the most extreme input is picked for a message.
_TYPICAL = {s.name: s.typical for s in PARAMETER_TABLE}
# The candidates by default: every parameter but the bounded ones (R's range is [0, 1]).
_EXTREME_BY_DEFAULT = tuple(s.name for s in PARAMETER_TABLE if not s.allowed.startswith("in "))
# The order the ranges are checked in (the first violated is named): > 0, then >= 0, then [0, 1].
_RANGE_ORDER = ("> 0", ">= 0", "in [0, 1]")


def most_extreme(p: Parameters, names: tuple[str, ...] | None = None) -> str:
    """The parameter among ``names`` farthest (in decades) from the reference case's value: the
    one a message about a numerical limit names."""
    names = names or _EXTREME_BY_DEFAULT

    def decades(name: str) -> float:
        v = abs(float(getattr(p, name)))
        return abs(math.log10(v) - math.log10(_TYPICAL[name])) if 0.0 < v < math.inf else 0.0

    return max(names, key=decades)


# The free scales: results in relative units (x/x_st, t/T, v/(x_st omega), S/(m1 x_st omega))
# do not depend on them. Within these ranges the solver works in the user's units; outside, its
# squares (energies, derivative bounds) would under- or overflow, and the entry points solve the
# same relative problem with the reference case's scales and convert the results back.
NATIVE_SCALES = {"x_st": (1e-30, 1e30), "m1": (1e-30, 1e30), "omega": (1e-10, 1e10)}
CANONICAL_SCALES = {"x_st": 1.0, "m1": 1.0, "omega": 10.0}


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

    Every value is a real number (numpy scalars too, stored as float; a bool is not a number),
    and the dimensional values derived from them (omega1, c1, k1, P0, ...) must be finite and,
    but for the damping and the gap, non-zero with a finite reciprocal.

    Raises
    ------
    TypeError
        A value that is not a real number (:class:`ArgumentTypeError`, also a ValueError).
    ValueError
        A value outside its range, or one that over- or underflows a derived value; the message
        names the parameter (the most extreme one, for a derived value) in backticks.
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
        for name in self.names():
            # Stored as float: numpy scalars (np.float32 arithmetic) and huge ints become plain
            # floats or a named error (an int of 400 digits raised OverflowError).
            object.__setattr__(self, name, finite_argument(name, getattr(self, name)))
        for allowed in _RANGE_ORDER:
            for spec in PARAMETER_TABLE:
                if spec.allowed == allowed:
                    check_value(spec.name, getattr(self, spec.name), spec.ok(getattr(self, spec.name)), allowed)

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
            "x_st omega": self.x_st * self.omega,
            "m1 x_st omega": self.m1 * self.x_st * self.omega,
        }
        # A derived value may be zero only where its relative parameter is (no damping, no gap).
        may_vanish = {"k1": self.delta1 == 0.0, "k2": self.delta2 == 0.0, "Delta0": self.gap == 0.0}
        for name, value in derived.items():
            if " " not in name:
                object.__setattr__(self, name, float(value))
            # Extreme but valid inputs can still over- or underflow the dimensional values: name
            # the input that is most extreme (a message once named c1 for theta = 1e-300).
            # (Its reciprocal must be finite too, but for those that may vanish: the model divides
            # by masses, stiffnesses and scales, and 1/5e-324 is inf.)
            vanishes = value == 0.0 and not may_vanish.get(name, False)
            tiny = name not in may_vanish and value != 0.0 and not math.isfinite(1.0 / value)
            if not math.isfinite(value) or vanishes or tiny:
                formula, inputs = _DERIVED[name]
                culprit = most_extreme(self, inputs)
                what = "overflows" if not math.isfinite(value) else "underflows to 0" if vanishes else "underflows"
                raise ValueError(
                    f"`{culprit}` = {getattr(self, culprit)!r} is not allowed with the other parameters: the "
                    f"dimensional {name} = {formula} {what}; {', '.join(inputs)} must keep it within the "
                    "floating-point range (about 1e-300 to 1e300)"
                )

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
        m = self.m1 * self.m2 / (self.m1 + self.m2)
        if m == 0.0 or not math.isfinite(m):  # m1 m2 under- or overflowed (m1 = 1e-300, 1e300)
            m = self.m1 * (self.mu / (1.0 + self.mu))
        return m

    def replace(self, **changes: float) -> Parameters:
        """A copy with some relative parameters changed (validated like the constructor)."""
        unknown = set(changes) - set(self.names())
        if unknown:
            name = sorted(unknown)[0]
            raise ValueError(f"`{name}` is not a parameter: allowed are {', '.join(self.names())}")
        return dataclasses.replace(self, **changes)

    def native_scales(self) -> bool:
        """Whether the free scales x_st, m1 and omega are within :data:`NATIVE_SCALES`, where the
        solver works in these units (else the entry points rescale, see :meth:`canonical`)."""
        return all(lo <= getattr(self, name) <= hi for name, (lo, hi) in NATIVE_SCALES.items())

    def canonical(self) -> Parameters:
        """The same relative problem with the reference case's free scales (x_st = 1 m,
        m1 = 1 kg, omega = 10 rad/s): results in relative units are the same."""
        return self.replace(**CANONICAL_SCALES)

    @staticmethod
    def names() -> tuple[str, ...]:
        """The relative parameters a user sets, in the paper's order."""
        return tuple(spec.name for spec in PARAMETER_TABLE)

    def to_dict(self) -> dict[str, float]:
        """The relative parameters as a plain dict (JSON-ready)."""
        return {name: float(getattr(self, name)) for name in self.names()}


REFERENCE = Parameters()
"""The paper's reference case of Fig. 2."""


def state_scale(p: Parameters):
    """The units of a state (x1, x2, x1', x2'): (x_st, x_st, x_st omega, x_st omega), an ndarray
    of shape (4,).

    Sections, Newton unknowns and mismatches are compared in these relative units, in which the
    paper's relative problem (Fig. 2: theta, mu, N, delta1, delta2, R, Delta0/x_st) is
    independent of the free scales x_st, m1 and omega.
    """
    import numpy as np  # (parameters.py otherwise needs no numpy)

    return np.array([p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega])


@dataclass(frozen=True)
class ScaleMap:
    """Converts dimensional values between two parameter sets with the same relative parameters
    (different free scales x_st, m1, omega): lengths, times, velocities and pulses.

    Times scale about t = 0, so the forcing's phase omega t is kept.

    Parameters
    ----------
    source, target : Parameters
    """

    source: Parameters
    target: Parameters

    def __post_init__(self) -> None:
        s, t = self.source, self.target
        # Ratios of the units themselves (each validated finite and non-zero by Parameters), so
        # that no factor overflows where the units do not.
        object.__setattr__(self, "length", t.x_st / s.x_st)
        object.__setattr__(self, "time", s.omega / t.omega)
        object.__setattr__(self, "velocity", (t.x_st * t.omega) / (s.x_st * s.omega))
        object.__setattr__(self, "impulse", (t.m1 * t.x_st * t.omega) / (s.m1 * s.x_st * s.omega))

    def full(self, y):
        """States (x1, x2, x1', x2'), shape (..., 4)."""
        return self._scaled(y, [self.length, self.length, self.velocity, self.velocity])

    def stuck(self, y):
        """States (x1, x1') of the bodies in contact, shape (..., 2)."""
        return self._scaled(y, [self.length, self.velocity])

    def apply(self, value, unit: str):
        """``value`` (a float or an array) in ``unit``: "time", "length", "velocity" or "impulse"."""
        return self._scaled(value, getattr(self, unit))

    def _scaled(self, value, factor):
        import numpy as np  # (parameters.py otherwise needs no numpy)

        with np.errstate(over="ignore", invalid="ignore"):
            out = np.asarray(value, dtype=float) * np.asarray(factor, dtype=float)
        if not np.all(np.isfinite(out)) and np.all(np.isfinite(value)):
            # The motion itself is beyond the floating-point range in the target's units (a
            # velocity 1e8 x_st omega with x_st = 1e300): a named error, not inf.
            t = self.target
            name = most_extreme(t, ("x_st", "m1", "omega"))
            raise ValueError(
                f"`{name}` = {getattr(t, name)!r} is not allowed with the other parameters: the motion's "
                f"dimensional values overflow in these units (x_st = {t.x_st!r} m, m1 = {t.m1!r} kg, "
                f"omega = {t.omega!r} rad/s); results in relative units do not depend on x_st, m1 and "
                "omega, so units nearer 1 give the same answer"
            )
        return float(out) if out.ndim == 0 else out
