"""The tangent map of the impacting flow: exact transition matrices, saltation matrices, QR.

The motion of the suppressor of Timofeev et al. (2019) is piecewise linear: between events it
is the exact flow of eq. (18) (:mod:`impactdamper.core.linear`), at an impact the pulse of
eqs. (21)-(22) changes the velocities, and in persistent contact the bodies move as one mass.
A perturbation dy of the state y = (x1, x2, x1', x2') is therefore carried exactly by

* **free flight** (or contact) for a time tau: the free mode's state-transition matrix
  e^{M tau} (or the contact mode's), the same matrix the solver uses for the motion, because
  the flow y' = M y + b sin(omega t) is linear in y;
* **an event** at a surface h(t, y) = 0 with a reset y+ = g(y-) (Jacobian G) and vector fields
  f- before and f+ after: the saltation matrix (Muller 1995; Leine & Nijmeijer 2004)

      S = G + (f+ - G f-) grad(h)^T / (grad(h) . f- + dh/dt),

  which adds to G the effect of the perturbed event time dt = -grad(h) . dy / (dh/dt along
  f-). The gap h = Delta0 - (x2 - x1) (eq. 20) has no explicit time dependence; the contact
  force that ends persistent contact does (the forcing acts on it directly: dh/dt =
  d_s omega cos(omega t)).

The events and their saltation matrices:

* **impact** (eqs. 21-22): G = J_R, the impact law's matrix; det S = R^2 (one R from the
  relative velocity's reversal, one from the ratio of the normal velocities after and before,
  which sets how the perturbed impact time shifts the state).
* **capture** into persistent contact (a plastic impact, or the limit of a chatter sequence):
  the reset keeps x1 and gives both bodies the centre-of-mass velocity; with the capture's
  time shift the saltation matrix is, in closed form (no division by the vanishing closing
  velocity),

      S_c = [[m1/M, m2/M, 0, 0], [k1 m2/M^2, -k1 m2/M^2, m1/M, m2/M]],   M = m1 + m2,

  a 2 x 4 matrix of rank 2: the perturbations of the relative motion (gap and closing
  velocity) are annihilated, those of the centre of mass pass into the contact mode. The
  tangent space drops from 4 to 2 dimensions, so the two exponents transverse to the
  constraint are -inf once a motion has been captured.
* **lift-off** (the contact force F falls through zero): G embeds (x1, x1') into the full
  state; since F = 0 there, the free and the constrained accelerations agree and S_l = G up
  to the residue of F at the located event (kept: it is the formula's, and tiny).
* **accumulation of impacts** (chatter): the solver resolves the bounces whose rebound height
  exceeds ``chatter_tol`` x_st, each with its own impact saltation matrix (entries grow like
  1/v_k, the flights between them shrink like v_k, and their product stays bounded), and
  replaces the rest of the sequence by its limit, a capture. At the accumulation point the
  tangent map is S_c above: its closed form is the limit of the exact chatter map's
  derivative, whose terms from the unresolved tail are O(v_k) and vanish with the closing
  velocity v_k of the last resolved bounce.

:func:`tangent_walk` carries an orthonormal frame of perturbations along the reference solver's
motion (:class:`~impactdamper.core.simulate.EventDrivenSolver`), period by period, multiplying
it by these matrices and re-orthonormalising it (QR, Benettin et al. 1980) after every event
and at every forcing period, in the relative state units (x_st, x_st omega); it returns each
period's growth (:class:`TangentRun`). The compiled backend's kernel
(:mod:`impactdamper.core.compiled.tangent`) mirrors these pure functions on the kernels' event
loop; :mod:`impactdamper.analysis.lyapunov` turns either's growths into exponents.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactdamper.core.impact_law import impact_jump
from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import Parameters, state_scale
from impactdamper.core.simulate import EventDrivenSolver
from impactdamper.core.steady import REBASE_PERIODS
from impactdamper.core.validation import Tolerances

__all__ = [
    "TangentRun",
    "tangent_walk",
    "saltation",
    "impact_saltation",
    "capture_saltation",
    "liftoff_saltation",
    "GRAZING_VELOCITY",
    "GAP_GRADIENT",
]

# A closing velocity (relative to x_st omega) below which an impact counts as grazing in the
# report: the saltation matrix grows like 1/v (the square-root singularity of grazing), and
# such events dominate the finite-time exponents of the period they fall in.
GRAZING_VELOCITY = 1e-6
# The gap's gradient in (x1, x2, x1', x2'): Delta = Delta0 - x2 + x1 (eq. 20).
GAP_GRADIENT = np.array([1.0, -1.0, 0.0, 0.0])
# A walk re-bases its solver's clock (a restart from the section state) only where the motion is
# in contact or its gap exceeds REBASE_CLEARANCE times the grazing resolution gap_tol x_st:
# a restart within the resolution puts the bodies on the stop and loses the departure of a
# lift-off just before the section (gap -23.68 of the gap sweep: a lift-off 4e-7 T before the
# section, restarted there, spent the solver's work bound at once). Elsewhere the re-basing
# waits for the next section (a clock a few periods older costs nothing).
REBASE_CLEARANCE = 1e3


# ----------------------------------------------------------------------------------------
# The tangent map's pieces: small pure functions of arrays (the compiled kernel mirrors them)
# ----------------------------------------------------------------------------------------
def _free_field(M: np.ndarray, b: np.ndarray, omega: float, t: float, y: np.ndarray) -> np.ndarray:
    """The vector field y' = M y + b sin(omega t) of a linear mode (eqs. 2, 9), shape (n,)."""
    return M @ y + b * math.sin(omega * t)


def saltation(G: np.ndarray, f_minus: np.ndarray, f_plus: np.ndarray, grad: np.ndarray, h_t: float = 0.0) -> np.ndarray:
    """Saltation matrix of an event at the surface h(t, y) = 0.

    S = G + (f+ - G f-) grad^T / (grad . f- + h_t): the reset's Jacobian G corrected for the
    perturbed event time (Muller 1995, eq. 13; Leine & Nijmeijer 2004, ch. 7).

    Parameters
    ----------
    G : ndarray, shape (m, n)
        Jacobian of the reset y+ = g(y-) (n: dimension before, m: after).
    f_minus : ndarray, shape (n,)
        Vector field before the event, at y-.
    f_plus : ndarray, shape (m,)
        Vector field after the event, at y+.
    grad : ndarray, shape (n,)
        Gradient of h in y.
    h_t : float
        Explicit time derivative of h.

    Returns
    -------
    ndarray, shape (m, n)
    """
    rate = float(grad @ f_minus) + h_t
    return G + np.outer(f_plus - G @ f_minus, grad) / rate


def impact_saltation(
    M: np.ndarray, b: np.ndarray, omega: float, jump: np.ndarray, t: float, before: np.ndarray
) -> np.ndarray:
    """Saltation matrix of an impact at (t, before) on the gap surface, shape (4, 4).

    Parameters
    ----------
    M, b, omega :
        The free mode (eqs. 2, 9): y' = M y + b sin(omega t).
    jump : ndarray, shape (4, 4)
        J_R, :func:`impactdamper.core.impact_law.impact_jump`.
    t : float
        Impact time, s.
    before : ndarray, shape (4,)
        (x1, x2, x1', x2') just before, on the stop.

    A touch at exactly zero closing velocity has no tangent map (the grazing impact's
    square-root singularity); it changes neither the state nor a perturbation that misses the
    stop, and the identity is returned.
    """
    f_minus = _free_field(M, b, omega, t, before)
    if float(GAP_GRADIENT @ f_minus) == 0.0:
        return np.eye(4)
    f_plus = _free_field(M, b, omega, t, jump @ before)
    return saltation(jump, f_minus, f_plus, GAP_GRADIENT)


def capture_saltation(m1: float, m2: float, k1: float) -> np.ndarray:
    """Saltation matrix of a capture into persistent contact, shape (2, 4): from (x1, x2, x1',
    x2') of the free motion just before the impact that ends in contact to (x1, x1') of the
    contact mode.

    The reset keeps x1 and gives both bodies the centre-of-mass velocity (the impacts conserve
    momentum); with the perturbed capture time, the general formula of :func:`saltation`
    reduces to this closed form (independent of the closing velocity, which cancels):

        [[m1/M, m2/M, 0, 0], [k1 m2/M^2, -k1 m2/M^2, m1/M, m2/M]],   M = m1 + m2.

    Its rows read the centre of mass's position and velocity (plus the damper k1's work over
    the time shift); the relative motion is annihilated (rank 2).
    """
    M = m1 + m2
    return np.array(
        [
            [m1 / M, m2 / M, 0.0, 0.0],
            [k1 * m2 / M**2, -k1 * m2 / M**2, m1 / M, m2 / M],
        ]
    )


def liftoff_saltation(
    M_free: np.ndarray,
    b_free: np.ndarray,
    M_stuck: np.ndarray,
    b_stuck: np.ndarray,
    omega: float,
    force_c: np.ndarray,
    force_ds: float,
    t: float,
    stuck: np.ndarray,
    Delta0: float,
) -> np.ndarray:
    """Saltation matrix of a lift-off at (t, stuck), shape (4, 2): from (x1, x1') in contact to
    (x1, x2, x1', x2') free.

    The surface is the contact force F = g0 + d_s sin(omega t) + c . (x1, x1') = 0 (explicitly
    time dependent); the reset embeds the contact state (x2 = x1 + Delta0, x2' = x1'). Since
    F = 0 the fields agree and S = G, but for the residue of F at the located event.
    """
    G = np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 1.0]])
    full = np.array([stuck[0], stuck[0] + Delta0, stuck[1], stuck[1]])
    f_minus = _free_field(M_stuck, b_stuck, omega, t, stuck)
    f_plus = _free_field(M_free, b_free, omega, t, full)
    return saltation(G, f_minus, f_plus, force_c, force_ds * omega * math.cos(omega * t))


def _orthonormalise(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """QR (Householder) of the tangent vectors' images A, shape (m, d).

    Returns
    -------
    Q : ndarray, shape (m, min(m, d))
        Orthonormal columns spanning the leading images.
    log_r : ndarray, shape (min(m, d),)
        log |R_ii|: the growth of the i-th direction orthogonal to the previous ones.
    """
    Q, R = np.linalg.qr(A)
    return Q, np.array([math.log(r) if r > 0.0 else -math.inf for r in np.abs(np.diag(R)).tolist()])


# ----------------------------------------------------------------------------------------
# A walk's record
# ----------------------------------------------------------------------------------------
@dataclass
class TangentRun:
    """Each period's growth of an orthonormal frame of perturbations along a motion: what a
    backend's ``lyapunov`` operation returns (:mod:`impactdamper.core.backends`).

    Attributes
    ----------
    increments : ndarray, shape (periods, 4)
        log |R_ii| summed over each averaged period (the finite-time exponents of each
        period, per period); -inf past the frame's dimension.
    sections : ndarray, shape (periods, 4)
        (x1, x2, x1', x2') at the start of each averaged period.
    dimension : int
        The frame's dimension at the end (4, or 2 once the motion was captured).
    impacts, captures, liftoffs, grazing : int
        Events in the averaged periods (``grazing``: impacts slower than
        :data:`GRAZING_VELOCITY` x_st omega).
    contact_time : float
        Time spent in persistent contact in the averaged periods, s.
    backend : str
        Who walked (``python``, ``compiled``).
    fallback : str
        Why the reference walked where another backend was asked ("" otherwise).
    """

    increments: np.ndarray
    sections: np.ndarray
    dimension: int
    impacts: int
    captures: int
    liftoffs: int
    grazing: int
    contact_time: float
    backend: str = "python"
    fallback: str = ""

    def event_counts(self) -> dict[str, int]:
        """The events of the averaged periods by kind: ``impacts``, ``captures``, ``liftoffs``,
        ``grazing`` (the counts a :class:`~impactdamper.analysis.lyapunov.LyapunovSpectrum` reports)."""
        return {"impacts": self.impacts, "captures": self.captures, "liftoffs": self.liftoffs, "grazing": self.grazing}


class _TangentFrame:
    """The orthonormal frame of perturbations and its growth, in relative units.

    The frame Q has shape (n, d): n = 4 in free motion, 2 in contact; d = 4 until a capture,
    then 2. ``log_growth`` (shape (4,)) accumulates log |R_ii| since the last reading;
    entries past d are -inf.
    """

    def __init__(self, model: Model, mode: str):
        p = model.p
        self.model = model
        self.mode = mode
        self.scale = {FREE: state_scale(p), STUCK: np.array([p.x_st, p.x_st * p.omega])}
        n = 4 if mode == FREE else 2
        self.Q = np.eye(n)
        self.log_growth = np.zeros(4)
        self.log_growth[n:] = -math.inf
        self.jump = impact_jump(p.m1, p.m2, p.R)
        self.capture = capture_saltation(p.m1, p.m2, p.k1)

    @property
    def dimension(self) -> int:
        return self.Q.shape[1]

    def _apply(self, A: np.ndarray, mode_in: str, mode_out: str) -> None:
        """Q <- D_out^-1 A D_in Q (the frame's images, not yet orthonormal)."""
        self.Q = (A * self.scale[mode_in][None, :] / self.scale[mode_out][:, None]) @ self.Q

    def orthonormalise(self) -> None:
        """Q <- its QR factor, log |R_ii| added to the growth (dimensions past Q's are lost)."""
        self.Q, log_r = _orthonormalise(self.Q)
        d = len(log_r)
        self.log_growth[:d] += log_r
        self.log_growth[d:] = -math.inf

    def flow(self, tau: float) -> None:
        """Exact transition matrix of the current mode over tau (the tangent of eq. 18).

        No re-orthonormalisation after it: over at most one period (the walk orthonormalises at
        every event and period) e^{M tau} is well conditioned (cond <= cond(V)
        e^{(max - min Re lambda) tau}, ~10 in the reference case), so the frame keeps its
        accuracy until the next event's QR."""
        if tau > 0.0:
            self._apply(self.model.mode(self.mode).propagator(tau), self.mode, self.mode)

    def impact(self, t: float, before: np.ndarray) -> None:
        lm = self.model.free
        S = impact_saltation(lm.M, lm.b, lm.omega, self.jump, t, before)
        self._apply(S, FREE, FREE)
        self.orthonormalise()

    def stick(self) -> None:
        if self.mode == STUCK:
            return  # (a restart on the stop: the motion was in contact already)
        self._apply(self.capture, FREE, STUCK)
        self.orthonormalise()
        self.mode = STUCK

    def liftoff(self, t: float, stuck_state: np.ndarray) -> None:
        m = self.model
        fn = m.contact_force
        S = liftoff_saltation(
            m.free.M, m.free.b, m.stuck.M, m.stuck.b, m.p.omega, fn.c, fn.d_s, t, stuck_state, m.p.Delta0
        )
        self._apply(S, STUCK, FREE)
        self.orthonormalise()
        self.mode = FREE

    def read(self) -> np.ndarray:
        """The growth since the last reading, shape (4,), and reset."""
        g = self.log_growth.copy()
        self.log_growth = np.where(np.isfinite(g), 0.0, -math.inf)
        return g


class _Run:
    """Algorithm No. 2 period by period from (t0, state), its clock set back to t0 every
    ``REBASE_PERIODS`` periods (as the settled-motion search does: a long run's absolute time
    would put ulp(t) rounding into every event time), at the first section after that which is
    a safe restart (:data:`REBASE_CLEARANCE`); hands out each period's new events."""

    def __init__(self, p: Parameters, t0: float, state: np.ndarray | None, tolerances: Tolerances):
        self.p, self.t0, self.tolerances = p, t0, tolerances
        self.solver = EventDrivenSolver(p, t0=t0, state=state, tolerances=tolerances)
        self.done = 0  # periods since the current solver's start
        self.seen = 0  # its events already handed out

    @property
    def t(self) -> float:
        """The current section's time on the current solver's clock, s."""
        return self.t0 + self.done * self.p.T

    def state(self) -> np.ndarray:
        return self.solver.state_at(self.t)

    def skip_events(self) -> None:
        self.seen = len(self.solver.trajectory.events)

    def period(self) -> list:
        """Advance one period; the events since the last call (a restart's own events, such as
        a capture at t0 of a motion in contact, included)."""
        if self.done >= REBASE_PERIODS:
            full = self.state()
            clear = self.p.Delta0 - (full[1] - full[0]) > REBASE_CLEARANCE * self.tolerances.gap_tol * self.p.x_st
            if self.solver.mode == STUCK or clear:
                self.solver = EventDrivenSolver(self.p, t0=self.t0, state=full, tolerances=self.tolerances)
                self.done, self.seen = 0, 0
        self.done += 1
        self.solver.advance(self.t)
        events = self.solver.trajectory.events[self.seen :]
        self.skip_events()
        return events


class _Counts:
    """The events of the averaged periods and the time in contact."""

    def __init__(self) -> None:
        self.impacts = self.captures = self.liftoffs = self.grazing = 0
        self.contact = 0.0


def _walk_period(frame: _TangentFrame, events: list, t: float, t_to: float, counts: _Counts | None, vscale: float):
    """Carry the frame over one period's events from t to t_to (``counts``: None in the
    warm-up). An impact followed at the same time by a capture is one event, the capture (its
    saltation matrix reads the state before the impact that ends in contact)."""
    i = 0
    while i < len(events):
        e = events[i]
        if frame.mode == STUCK and counts is not None:
            counts.contact += e.t - t
        frame.flow(e.t - t)
        t = e.t
        if e.kind == "impact":
            captured = i + 1 < len(events) and events[i + 1].kind == "stick" and events[i + 1].t == e.t
            if counts is not None:
                counts.impacts += 1
                counts.grazing += bool(e.velocity < GRAZING_VELOCITY * vscale)
                counts.captures += captured
            if captured:
                frame.stick()
                i += 1
            else:
                frame.impact(e.t, e.before)
        elif e.kind == "stick":
            if counts is not None:
                counts.captures += frame.mode == FREE
            frame.stick()
        elif e.kind == "liftoff":
            if counts is not None:
                counts.liftoffs += 1
            frame.liftoff(e.t, np.array([e.before[0], e.before[2]]))
        i += 1
    if frame.mode == STUCK and counts is not None:
        counts.contact += t_to - t
    frame.flow(t_to - t)
    frame.orthonormalise()


def tangent_walk(
    p: Parameters,
    t0: float,
    state: np.ndarray | None,
    tolerances: Tolerances,
    periods: int,
    transient: int,
    warmup: int,
) -> TangentRun:
    """The reference's walk: the frame's growth per period along Algorithm No. 2's motion.

    From ``state`` at ``t0`` (None: the paper's step 1) the motion runs ``transient`` periods;
    then the frame (the identity, in the mode the motion is in) is carried along it, the first
    ``warmup`` periods of its growth discarded and the next ``periods`` returned. Arguments
    validated by the caller (:func:`impactdamper.analysis.lyapunov.lyapunov_spectrum`), ``p``
    in the native scales, t0 in [0, T).

    Raises
    ------
    SearchLimitError
        The motion needs more work than the event solver's bound.
    """
    T = p.T
    run = _Run(p, t0, state, tolerances)
    for _ in range(transient):
        run.period()
    run.skip_events()  # the frame starts now: the start's own events are the transient's
    frame = _TangentFrame(Model(p), run.solver.mode)
    increments = np.empty((periods, 4))
    sections = np.empty((periods, 4))
    counts = _Counts()
    vscale = p.x_st * p.omega
    for n in range(warmup + periods):
        averaged = n >= warmup
        if averaged:
            sections[n - warmup] = run.state()
        events = run.period()
        _walk_period(frame, events, run.t - T, run.t, counts if averaged else None, vscale)
        growth = frame.read()
        if averaged:
            increments[n - warmup] = growth
        if frame.mode != run.solver.mode:  # (the walk and the solver agree on the mode)
            raise RuntimeError(f"tangent mode {frame.mode} != solver mode {run.solver.mode} at t = {run.t!r}")
    return TangentRun(
        increments=increments,
        sections=sections,
        dimension=frame.dimension,
        impacts=counts.impacts,
        captures=counts.captures,
        liftoffs=counts.liftoffs,
        grazing=counts.grazing,
        contact_time=counts.contact,
    )
