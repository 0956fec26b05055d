"""Lyapunov exponents of the impacting flow: exact tangent maps, saltation matrices and QR.

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

The exponents are the growth rates of the QR (Gram-Schmidt) factorisation of the product of
these matrices along the motion (Benettin et al. 1980), re-orthonormalised at every event and
at every forcing period, in the relative state units (x_st, x_st omega). The forcing makes the
flow non-autonomous: a perturbation along the orbit is not a solution (the forcing's phase is
fixed), so there is no trivial zero exponent, and at a stable periodic orbit of period k T
all four exponents are log|mu_i| / k per forcing period, mu_i its Floquet multipliers.

Averages. The per-period increments of log |R_ii| are averaged with the smooth weight
w(s) = exp(-1/(s (1 - s))), s in (0, 1) across the averaged periods (the weighted Birkhoff
average of Das & Yorke 2017). On a periodic or quasi-periodic motion the increments are a
smooth function of a rotation (a complex pair of multipliers turns the frame within its
plane), and the weighted average converges faster than any power of the run's length, where
the plain average converges like 1/length (at the stated case, 2000 periods, against the
Floquet multipliers: 4e-12 against 3e-4); on a chaotic motion both converge like 1/sqrt(length). The exponent is the weighted
average over all the averaged periods; its error is the standard error of the same weighted
average over each of ``blocks`` blocks (a fair estimate for a chaotic motion, whose blocks are
nearly independent; an overestimate for a regular one, whose blocks are shorter than the run).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.core.model import FREE, STUCK, Model
from impactdamper.core.parameters import Parameters, ScaleMap, require_parameters, state_scale
from impactdamper.core.simulate import EventDrivenSolver
from impactdamper.core.steady import start_in_first_period
from impactdamper.core.validation import Tolerances, check_state, check_tolerances, finite_argument, integer_argument

__all__ = [
    "LyapunovSpectrum",
    "lyapunov_spectrum",
    "classify_spectrum",
    "LABELS",
    "free_field",
    "saltation",
    "impact_jump",
    "impact_saltation",
    "capture_saltation",
    "liftoff_saltation",
    "orthonormalise",
    "birkhoff_weights",
    "SIGNIFICANCE",
    "ZERO_BAND",
]

# --- run lengths (forcing periods) ------------------------------------------------------
# Periods of motion discarded before the tangent product starts: the reference case's slowest
# stable mode decays by e^-0.34 a period, so 500 periods bring a motion from the paper's step 1
# onto its attractor to rounding (e^-170); near a bifurcation, pass more.
DEFAULT_TRANSIENT = 500
# Periods of tangent product discarded while the orthonormal frame turns onto the Lyapunov
# vectors: its misalignment decays like e^{-(lambda_i - lambda_{i+1}) n}, and the smallest gap
# between distinct exponents at the test orbits is 0.056 a period (gap +14), so 200 periods
# leave < 2e-5, which the averaging weight (vanishing at the ends of the run) suppresses further.
DEFAULT_WARMUP = 200
# Periods averaged, and the blocks they are split into for the error estimate (10 blocks of
# 200: the standard error of a mean of 10 is itself known to ~25 %).
DEFAULT_PERIODS = 2000
DEFAULT_BLOCKS = 10
# Bounds on the work of one call (the pure-Python loop advances ~2000-6000 periods a second).
MAX_PERIODS = 1_000_000
# The solver restarts from the section state with its clock back at t0 every REBASE_PERIODS
# periods (the forcing is T-periodic), as steady_state does: a long run's absolute time would
# put ulp(t) rounding into every event time.
REBASE_PERIODS = 100

# --- labels -----------------------------------------------------------------------------
LABELS = ("chaotic", "quasi-periodic", "periodic", "not settled")
# "Beyond its error" means more than SIGNIFICANCE standard errors of the block mean: with 10
# blocks (9 degrees of freedom, Student's t) a one-sided 3-sigma excursion happens by chance
# with probability ~0.7 %.
SIGNIFICANCE = 3.0
# Exponents (per forcing period) within ZERO_BAND of zero are not told from zero: a
# perturbation growing at 1e-3 a period changes by a factor e^2 over the default 2000 periods,
# too little to separate a weakly chaotic motion from a torus or a slowly decaying transient.
# It also holds the torus's estimates (gap -10.2: exponent 2.5e-8, block standard error 3e-5).
ZERO_BAND = 1e-3
# A closing velocity (relative to x_st omega) below which an impact counts as grazing in the
# report: the saltation matrix grows like 1/v (the square-root singularity of grazing), and
# such events dominate the finite-time exponents of the period they fall in.
GRAZING_VELOCITY = 1e-6

# The gap's gradient in (x1, x2, x1', x2'): Delta = Delta0 - x2 + x1 (eq. 20).
GAP_GRADIENT = np.array([1.0, -1.0, 0.0, 0.0])


# ----------------------------------------------------------------------------------------
# The tangent map's pieces: small pure functions of arrays (a compiled kernel mirrors them)
# ----------------------------------------------------------------------------------------
def free_field(M: np.ndarray, b: np.ndarray, omega: float, t: float, y: np.ndarray) -> np.ndarray:
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


def impact_jump(m1: float, m2: float, R: float) -> np.ndarray:
    """Jacobian J_R of the impact law, eqs. (21)-(22), on (x1, x2, x1', x2'), shape (4, 4).

    The pulse S = m1 m2/(m1 + m2) (1 + R) (x2' - x1') adds S/m1 to x1' and -S/m2 to x2': so
    x1'+ = x1' + (1 + R) m2/M (x2' - x1') and x2'+ = x2' - (1 + R) m1/M (x2' - x1'), M = m1 + m2.
    Positions are unchanged. det J_R = -R.
    """
    M = m1 + m2
    a, c = (1.0 + R) * m2 / M, (1.0 + R) * m1 / M
    return np.array(
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0 - a, a],
            [0.0, 0.0, c, 1.0 - c],
        ]
    )


def impact_saltation(
    M: np.ndarray, b: np.ndarray, omega: float, jump: np.ndarray, t: float, before: np.ndarray
) -> np.ndarray:
    """Saltation matrix of an impact at (t, before) on the gap surface, shape (4, 4).

    Parameters
    ----------
    M, b, omega :
        The free mode (eqs. 2, 9): y' = M y + b sin(omega t).
    jump : ndarray, shape (4, 4)
        :func:`impact_jump`.
    t : float
        Impact time, s.
    before : ndarray, shape (4,)
        (x1, x2, x1', x2') just before, on the stop.

    A touch at exactly zero closing velocity has no tangent map (the grazing impact's
    square-root singularity); it changes neither the state nor a perturbation that misses the
    stop, and the identity is returned.
    """
    f_minus = free_field(M, b, omega, t, before)
    if float(GAP_GRADIENT @ f_minus) == 0.0:
        return np.eye(4)
    f_plus = free_field(M, b, omega, t, jump @ before)
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
    f_minus = free_field(M_stuck, b_stuck, omega, t, stuck)
    f_plus = free_field(M_free, b_free, omega, t, full)
    return saltation(G, f_minus, f_plus, force_c, force_ds * omega * math.cos(omega * t))


def orthonormalise(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """QR (Gram-Schmidt) of the tangent vectors' images A, shape (m, d).

    Returns
    -------
    Q : ndarray, shape (m, min(m, d))
        Orthonormal columns spanning the leading images.
    log_r : ndarray, shape (min(m, d),)
        log |R_ii|: the growth of the i-th direction orthogonal to the previous ones.
    """
    Q, R = np.linalg.qr(A)
    return Q, np.array([math.log(r) if r > 0.0 else -math.inf for r in np.abs(np.diag(R)).tolist()])


def birkhoff_weights(n: int) -> np.ndarray:
    """Weights of the weighted Birkhoff average over n samples, shape (n,), summing to 1:
    w(s) = exp(-1/(s (1 - s))) at s = (i + 1/2)/n (Das & Yorke 2017)."""
    s = (np.arange(n) + 0.5) / n
    w = np.exp(-1.0 / (s * (1.0 - s)))
    return w / w.sum()


# ----------------------------------------------------------------------------------------
# The result
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LyapunovSpectrum:
    """The Lyapunov spectrum of a motion, per forcing period.

    Attributes
    ----------
    p : Parameters
    exponents : ndarray, shape (4,)
        Lyapunov exponents of (x1, x2, x1', x2') per forcing period T (lambda T, comparable
        with log|mu| / k at a periodic orbit of period k T), largest first; ``-inf`` for the
        directions a capture into persistent contact annihilates. The report uses these.
    errors : ndarray, shape (4,)
        Standard error of each: the standard deviation of the block averages over
        sqrt(blocks) (nan for -inf exponents; see the module docstring).
    spreads : ndarray, shape (4,)
        Largest minus smallest block average (nan for -inf exponents).
    block_averages : ndarray, shape (blocks, 4)
        Weighted average of the per-period increments over each block.
    increments : ndarray, shape (periods, 4)
        log |R_ii| summed over each averaged period (the finite-time exponents of each period).
    sections : ndarray, shape (periods, 4)
        The state (x1, x2, x1', x2') at the start of each averaged period, at times
        ``t_section`` + n T (the forcing's phase is the same at each).
    t_section : float
        Forcing phase time of the sections, s, in [0, T).
    dimension : int
        Dimension of the tangent space at the end (4, or 2 once the motion was captured).
    periods, transient, warmup, blocks : int
        Periods averaged; periods of motion discarded; periods of tangent product discarded;
        blocks of the error estimate.
    impacts, captures, liftoffs, grazing : int
        Events in the averaged periods (``grazing``: impacts slower than ``GRAZING_VELOCITY``
        x_st omega).
    contact_time : float
        Share of the averaged time spent in persistent contact.
    method : str
    backend : str
    """

    p: Parameters = field(repr=False)
    exponents: np.ndarray
    errors: np.ndarray
    spreads: np.ndarray
    block_averages: np.ndarray = field(repr=False)
    increments: np.ndarray = field(repr=False)
    sections: np.ndarray = field(repr=False)
    t_section: float
    dimension: int
    periods: int
    transient: int
    warmup: int
    blocks: int
    impacts: int
    captures: int
    liftoffs: int
    grazing: int
    contact_time: float
    method: str = "tangent map: exact flows, saltation matrices, QR per event and period"
    backend: str = "python"

    @property
    def exponents_per_second(self) -> np.ndarray:
        """The exponents in 1/s (lambda = exponents / T), shape (4,)."""
        return self.exponents / self.p.T

    @property
    def label(self) -> str:
        """:func:`classify_spectrum` of this spectrum."""
        return classify_spectrum(self)

    def to_dict(self) -> dict:
        """A JSON-ready summary (exponents per period and per second, errors, counts, label)."""

        def listed(a):
            return [None if not math.isfinite(v) else float(v) for v in a]

        return {
            "exponents": listed(self.exponents),
            "exponents_per_second": listed(self.exponents_per_second),
            "errors": listed(self.errors),
            "spreads": listed(self.spreads),
            "label": self.label,
            "dimension": self.dimension,
            "periods": self.periods,
            "transient": self.transient,
            "warmup": self.warmup,
            "blocks": self.blocks,
            "impacts": self.impacts,
            "captures": self.captures,
            "liftoffs": self.liftoffs,
            "grazing": self.grazing,
            "contact_time": self.contact_time,
            "method": self.method,
            "backend": self.backend,
            "parameters": self.p.to_dict(),
        }


def classify_spectrum(s: LyapunovSpectrum) -> str:
    """What a motion is, from its spectrum: one of :data:`LABELS`.

    * ``chaotic``: the largest exponent is positive beyond its error (more than
      ``SIGNIFICANCE`` standard errors) and beyond ``ZERO_BAND``;
    * ``periodic``: the largest exponent (hence all) is negative in the same sense: every
      perturbation decays (the stroboscopic map has no neutral direction, there being no
      trivial zero exponent for the forced, non-autonomous flow);
    * ``quasi-periodic``: the largest exponent is resolved to be zero (its interval of
      ``SIGNIFICANCE`` standard errors lies inside +-``ZERO_BAND``) and the next is negative
      beyond its error: one neutral direction, along an invariant torus;
    * ``not settled``: none of these resolved within the run.
    """
    lam, err = s.exponents, s.errors

    def positive(i: int) -> bool:
        return bool(lam[i] - SIGNIFICANCE * err[i] > 0.0 and lam[i] > ZERO_BAND)

    def negative(i: int) -> bool:
        return bool(lam[i] == -math.inf or (lam[i] + SIGNIFICANCE * err[i] < 0.0 and lam[i] < -ZERO_BAND))

    if positive(0):
        return "chaotic"
    if negative(0):
        return "periodic"
    near_zero = abs(lam[0]) + SIGNIFICANCE * err[0] <= ZERO_BAND
    if near_zero and negative(1):
        return "quasi-periodic"
    return "not settled"


# ----------------------------------------------------------------------------------------
# The driver
# ----------------------------------------------------------------------------------------
def lyapunov_spectrum(
    p: Parameters,
    *,
    periods: int = DEFAULT_PERIODS,
    transient: int = DEFAULT_TRANSIENT,
    warmup: int = DEFAULT_WARMUP,
    blocks: int = DEFAULT_BLOCKS,
    t0: float = 0.0,
    state: np.ndarray | None = None,
    tolerances: Tolerances | None = None,
) -> LyapunovSpectrum:
    """The four Lyapunov exponents of the motion of Algorithm No. 2 (eqs. 18-22, with contact
    modes), from the exact tangent map along it.

    From ``state`` at ``t0`` (default the paper's step 1), the motion runs ``transient``
    periods; then an orthonormal frame of perturbations is carried by the exact free-flight and
    contact transition matrices and the saltation matrices of the impacts, captures and
    lift-offs (see the module docstring), re-orthonormalised after every event and every
    period; the first ``warmup`` periods of that product are discarded and the next
    ``periods`` averaged.

    Parameters
    ----------
    p : Parameters
    periods : int
        Forcing periods averaged, a multiple of ``blocks``.
    transient, warmup : int
        Periods of motion, then of tangent product, discarded (>= 0).
    blocks : int
        Blocks of the error estimate, >= 2.
    t0 : float
        Start time, s (its forcing phase is kept).
    state : ndarray, shape (4,), optional
        (x1, x2, x1', x2') at t0, e.g. a settled motion's section; default the paper's step 1.
    tolerances : Tolerances, optional
        The event solver's tolerances.

    Returns
    -------
    LyapunovSpectrum

    Raises
    ------
    TypeError, ValueError
        A bad argument, named.
    SearchLimitError
        The motion needs more work than the event solver's bound.
    """
    p = require_parameters(p)
    blocks = integer_argument("blocks", blocks, 2, MAX_PERIODS)
    periods = integer_argument("periods", periods, blocks, MAX_PERIODS)
    if periods % blocks:
        raise ValueError(f"`periods` = {periods!r} is not allowed: must be a multiple of `blocks` = {blocks!r}")
    transient = integer_argument("transient", transient, 0, MAX_PERIODS)
    warmup = integer_argument("warmup", warmup, 0, MAX_PERIODS)
    t0 = finite_argument("t0", t0)
    tolerances = check_tolerances(tolerances)
    state = check_state(state, p)
    # The forcing's phase at t0, in [0, T): the run is the same motion shifted by whole periods.
    t_start = start_in_first_period(p, t0)
    if not p.native_scales():
        # The same relative problem in the reference case's units: exponents per period and the
        # relative quantities do not depend on the free scales.
        q = p.canonical()
        to_q, to_p = ScaleMap(p, q), ScaleMap(q, p)
        s = _spectrum(
            q,
            to_q.apply(t_start, "time"),
            None if state is None else to_q.full(state),
            tolerances,
            periods,
            transient,
            warmup,
            blocks,
        )
        return _replace_scales(s, p, to_p)
    return _spectrum(p, t_start, state, tolerances, periods, transient, warmup, blocks)


def _replace_scales(s: LyapunovSpectrum, p: Parameters, scales: ScaleMap) -> LyapunovSpectrum:
    return dataclasses.replace(
        s, p=p, sections=scales.full(s.sections), t_section=float(scales.apply(s.t_section, "time"))
    )


class _Tangent:
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
        self.Q, log_r = orthonormalise(self.Q)
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
    ``REBASE_PERIODS`` periods; hands out each period's new events."""

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
            self.solver = EventDrivenSolver(self.p, t0=self.t0, state=full, tolerances=self.tolerances)
            self.done, self.seen = 0, 0
        self.done += 1
        self.solver.advance(self.t)
        events = self.solver.trajectory.events[self.seen :]
        self.skip_events()
        return events


def _spectrum(
    p: Parameters,
    t0: float,
    state: np.ndarray | None,
    tolerances: Tolerances,
    periods: int,
    transient: int,
    warmup: int,
    blocks: int,
) -> LyapunovSpectrum:
    """lyapunov_spectrum on validated arguments, t0 in [0, T), in native scales."""
    T = p.T
    run = _Run(p, t0, state, tolerances)
    for _ in range(transient):
        run.period()
    run.skip_events()  # the tangent starts now: the start's own events are the transient's
    tangent = _Tangent(Model(p), run.solver.mode)
    increments = np.empty((periods, 4))
    sections = np.empty((periods, 4))
    counts = dict.fromkeys(("impact", "capture", "liftoff", "grazing"), 0)
    contact = 0.0
    vscale = p.x_st * p.omega
    for n in range(warmup + periods):
        averaged = n >= warmup
        if averaged:
            sections[n - warmup] = run.state()
        events = run.period()
        t, t_to = run.t - T, run.t
        i = 0
        while i < len(events):
            e = events[i]
            if tangent.mode == STUCK and averaged:
                contact += e.t - t
            tangent.flow(e.t - t)
            t = e.t
            if e.kind == "impact":
                captured = i + 1 < len(events) and events[i + 1].kind == "stick" and events[i + 1].t == e.t
                if averaged:
                    counts["impact"] += 1
                    counts["grazing"] += bool(e.velocity < GRAZING_VELOCITY * vscale)
                    counts["capture"] += captured
                if captured:
                    # The capture's saltation matrix reads the state before the impact that
                    # ends in contact (impact and capture are one event; see capture_saltation).
                    tangent.stick()
                    i += 1
                else:
                    tangent.impact(e.t, e.before)
            elif e.kind == "stick":
                counts["capture"] += bool(averaged and tangent.mode == FREE)
                tangent.stick()
            elif e.kind == "liftoff":
                counts["liftoff"] += averaged
                tangent.liftoff(e.t, np.array([e.before[0], e.before[2]]))
            i += 1
        if tangent.mode == STUCK and averaged:
            contact += t_to - t
        tangent.flow(t_to - t)
        tangent.orthonormalise()
        growth = tangent.read()
        if averaged:
            increments[n - warmup] = growth
        if tangent.mode != run.solver.mode:  # (the walk and the solver agree on the mode)
            raise RuntimeError(f"tangent mode {tangent.mode} != solver mode {run.solver.mode} at t = {t_to!r}")
    return _summarise(
        p, increments, sections, t0, tangent.dimension, transient, warmup, blocks, counts, contact / (periods * T)
    )


def _summarise(
    p: Parameters,
    increments: np.ndarray,
    sections: np.ndarray,
    t0: float,
    dimension: int,
    transient: int,
    warmup: int,
    blocks: int,
    counts: dict,
    contact_time: float,
) -> LyapunovSpectrum:
    periods = len(increments)
    length = periods // blocks
    finite = np.isfinite(increments).all(axis=0)
    exponents = np.full(4, -math.inf)
    block_avg = np.full((blocks, 4), -math.inf)
    errors = np.full(4, math.nan)
    spreads = np.full(4, math.nan)
    exponents[finite] = birkhoff_weights(periods) @ increments[:, finite]
    block_avg[:, finite] = np.einsum(
        "bnj,n->bj", increments[:, finite].reshape(blocks, length, -1), birkhoff_weights(length)
    )
    errors[finite] = block_avg[:, finite].std(axis=0, ddof=1) / math.sqrt(blocks)
    spreads[finite] = np.ptp(block_avg[:, finite], axis=0)
    return LyapunovSpectrum(
        p=p,
        exponents=exponents,
        errors=errors,
        spreads=spreads,
        block_averages=block_avg,
        increments=increments,
        sections=sections,
        t_section=float(t0),
        dimension=int(dimension),
        periods=periods,
        transient=transient,
        warmup=warmup,
        blocks=blocks,
        impacts=int(counts["impact"]),
        captures=int(counts["capture"]),
        liftoffs=int(counts["liftoff"]),
        grazing=int(counts["grazing"]),
        contact_time=float(contact_time),
    )
