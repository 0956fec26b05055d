"""The suppressor model: its two modes, the gap, the contact force and the impact law.

Fig. 1 of Timofeev et al. (2019): the object m1 on (c1, k1) under P0 sin(omega t), the
suppressor m2 on (c2, k2) attached to the object, and a one-sided stop. The gap is

    Delta = Delta0 - (x2 - x1)        (eq. 20),

and Delta >= 0 always. Two modes of motion:

* ``free``: the bodies apart (Delta > 0), eqs. (2) and (9), state (x1, x2, x1', x2');
* ``stuck``: the bodies in persistent contact (Delta = 0), moving as one mass m1 + m2 on
  c1, k1, state (x1, x1'). The stop then pushes the bodies apart with the force

      F = -m2 x1'' - c2 Delta0 >= 0,

  and the contact ends (lift-off) when F falls through zero. This mode is not in the paper;
  it is the paper's "object and suppressor move together" regime, and the limit of an
  accumulation of impacts (chatter).

At an impact (Delta = 0 while closing) the stereomechanical law of eqs. (14), (21)-(22) acts:
the pulse S = m1 m2/(m1 + m2) (1 + R) v, with v = x2' - x1' the closing velocity, changes
x1' by +S/m1 and x2' by -S/m2, so the relative velocity becomes -R v and momentum is conserved
(stated once, in :mod:`impactdamper.core.impact_law`).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from impactdamper.core.events import LinearFunctional
from impactdamper.core.impact_law import apply_impact
from impactdamper.core.linear import MODE_CACHE_SIZE, LinearMode, free_mode, stuck_mode
from impactdamper.core.parameters import LINEAR_PARAMETERS, Parameters, most_extreme

__all__ = ["Model", "model_of", "FREE", "STUCK"]

FREE = "free"
STUCK = "stuck"
# Largest forced-response amplitude, relative to x_st, that the closed form resolves: the motion
# is the forced response plus a free response (eqs. 10-11, 18), and near an undamped resonance
# both are huge and cancel; rounding then leaves ~1e-16 times this, which must stay far below
# the results' accuracy (~1e-8 x_st, beyond the grazing tolerance's reach already).
FORCED_AMPLITUDE_LIMIT = 1e8


class Model:
    """The suppressor's modes, event functions and impact law, for one parameter set.

    Attributes
    ----------
    p : Parameters
    free, stuck : LinearMode
        The two modes of motion.
    gap : LinearFunctional
        Delta(t) on the free mode, eq. (20), in m.
    contact_force : LinearFunctional
        F(t) on the stuck mode, in N.
    """

    def __init__(self, p: Parameters):
        self.p = p
        try:
            self.free: LinearMode = free_mode(p)
            self.stuck: LinearMode = stuck_mode(p)
            problem = "" if self.free.finite and self.stuck.finite else "powers of the state matrix overflow"
        except np.linalg.LinAlgError as err:
            # (mu = 1e300: the energy matrix diag(c, m) loses its small entries to rounding.)
            problem = str(err)
        if problem:
            name = most_extreme(p, LINEAR_PARAMETERS)
            raise ValueError(
                f"`{name}` = {getattr(p, name)!r} is not allowed with the other parameters: the model's "
                f"matrices leave the floating-point range ({problem}); allowed are parameters nearer the "
                "reference case (theta = 1, mu = 0.08, N = 0.5, delta1 = delta2 = 0.05)"
            )
        if not self.free.forced_amplitude <= FORCED_AMPLITUDE_LIMIT * p.x_st:
            raise ValueError(self.resonance_message(FREE))
        # The bodies in contact resonate only with delta1 = 0 at theta = 1/sqrt(1 + mu); that
        # matters only if they stay in contact, so the solver reports it when they do.
        self.stuck_resonant = not self.stuck.forced_amplitude <= FORCED_AMPLITUDE_LIMIT * p.x_st
        self.gap = LinearFunctional(self.free, np.array([1.0, -1.0, 0.0, 0.0]), p.Delta0)
        m = p.m1 + p.m2
        # F = -m2 x1'' - c2 Delta0 with (m1 + m2) x1'' = P0 sin(wt) - k1 x1' - c1 x1.
        with np.errstate(invalid="ignore", over="ignore"):  # (inf amplitudes when stuck_resonant)
            self.contact_force = LinearFunctional(
                self.stuck,
                np.array([p.m2 * p.c1 / m, p.m2 * p.k1 / m]),
                -p.c2 * p.Delta0,
                d_s=-p.m2 * p.P0 / m,
            )
        # Scales that make tolerances relative: length x_st, time 1/omega.
        self.length_scale = p.x_st
        self.velocity_scale = p.x_st * p.omega
        self.force_scale = p.reduced_mass * p.x_st * max(p.omega, p.omega1, p.omega2) ** 2

    def mode(self, name: str) -> LinearMode:
        return self.free if name == FREE else self.stuck

    def resonance_message(self, mode: str) -> str:
        """One line naming theta: the forcing at an (almost) undamped natural frequency of a mode,
        where the forced response is unbounded and the closed form has no periodic solution."""
        p, lm = self.p, self.mode(mode)
        lam = lm.roots[np.argmin(np.abs(lm.roots - 1j * p.omega))]
        what = "the free suppressor" if mode == FREE else "the bodies in contact (omega1/sqrt(1 + mu))"
        damping = f"delta1 = {p.delta1!r}, delta2 = {p.delta2!r}" if mode == FREE else f"delta1 = {p.delta1!r}"
        fix = "delta1, delta2" if mode == FREE else "delta1"
        undamped = (p.delta1 == 0.0 and p.delta2 == 0.0) if mode == FREE else p.delta1 == 0.0
        response = (
            "is unbounded (eqs. 10-11 have no periodic solution)"
            if undamped
            else f"is beyond what the closed form resolves (eqs. 10-11, {FORCED_AMPLITUDE_LIMIT:.0e} x_st)"
        )
        return (
            f"`theta` = {p.theta!r} is not allowed with {damping}: {'' if undamped else 'nearly '}undamped "
            f"resonance, the forcing is at a natural frequency of {what}, {abs(lam.imag) / p.omega1:.9g} "
            f"omega1, where the forced response (|x_p|/x_st = {lm.forced_amplitude / p.x_st:.3g}) {response}; "
            f"add damping ({fix} > 0) or move theta"
        )

    # --- coordinates ---------------------------------------------------------------
    def full_state(self, mode: str, y: np.ndarray) -> np.ndarray:
        """(x1, x2, x1', x2') from a state of either mode, shape (..., 4)."""
        y = np.asarray(y, dtype=float)
        if mode == FREE:
            return y
        x1, v1 = y[..., 0], y[..., 1]
        return np.stack([x1, x1 + self.p.Delta0, v1, v1], axis=-1)

    def relative(self, full: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The paper's relative coordinates x1_bar = x1/x_st, x2_bar = (x2 - Delta0)/x_st."""
        return full[..., 0] / self.p.x_st, (full[..., 1] - self.p.Delta0) / self.p.x_st

    def gap_of(self, full: np.ndarray) -> np.ndarray:
        """Delta = Delta0 - (x2 - x1), m."""
        return self.p.Delta0 - (full[..., 1] - full[..., 0])

    # --- contact -------------------------------------------------------------------
    def impact(self, full: np.ndarray) -> tuple[np.ndarray, float, float]:
        """Apply eqs. (21)-(22) to a state at Delta = 0 (:func:`~impactdamper.core.impact_law.apply_impact`).

        Returns
        -------
        after : ndarray, shape (4,)
            State just after the impact.
        v : float
            Closing velocity x2' - x1' before the impact (>= 0; a grazing touch gives ~0).
        S : float
            The pulse, N s.
        """
        return apply_impact(self.p, full)

    def stick(self, full: np.ndarray) -> tuple[np.ndarray, float]:
        """Plastic capture into persistent contact: both bodies take the centre-of-mass
        velocity (momentum conserved). Returns the stuck state (x1, x1') and the pulse."""
        p = self.p
        v_cm = (p.m1 * full[2] + p.m2 * full[3]) / (p.m1 + p.m2)
        return np.array([full[0], v_cm]), p.m1 * (v_cm - full[2])

    def force_in_contact(self, t: float, full: np.ndarray) -> float:
        """Contact force F the stop would carry if the bodies moved together from here, N."""
        fn = self.contact_force
        c = fn.c
        return fn.g0 + fn.d_s * math.sin(self.p.omega * t) + c[0] * full[0] + c[1] * full[2]

    def gap_derivatives(self, t: float, full: np.ndarray, orders: int = 4) -> np.ndarray:
        """Delta and its first ``orders - 1`` time derivatives in the free mode at (t, full)."""
        return np.array([float(self.gap.of_state(t, full, k)) for k in range(orders)])

    def energy(self, full: np.ndarray) -> np.ndarray:
        """Mechanical energy of the two bodies (kinetic plus springs), J."""
        p = self.p
        x1, x2, v1, v2 = (full[..., i] for i in range(4))
        return 0.5 * (p.m1 * v1**2 + p.m2 * v2**2 + p.c1 * x1**2 + p.c2 * (x2 - x1) ** 2)


@functools.lru_cache(maxsize=MODE_CACHE_SIZE)
def model_of(p: Parameters) -> Model:
    """``Model(p)``, built once per parameter set and shared: every run of the solvers starts by
    building its model (its modes are cached already, its functionals' derivative bounds are
    not): 6 % of a 10-period run under py-spy. A Model is never changed after
    ``__init__`` (its modes, functionals and scales are read only), so sharing it is safe; a
    refused parameter set raises each time (lru_cache keeps no exception)."""
    return Model(p)
