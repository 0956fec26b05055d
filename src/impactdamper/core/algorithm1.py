"""Algorithm No. 1 of Timofeev et al. (2019): the one-impact-per-period orbit in closed form.

Assume one impact per forcing period T, at t = 0 in time counted from the impact. The free
part of the motion is the T-periodic response x_s to a unit pulse pair (+1 on the object,
-1 on the suppressor), eqs. (6)-(8); the motion is x = x_p + S x_s, eq. (1). The pulse S
follows from the impact law, eq. (15), and the impact phase eps from the gap being zero at
the impact, eq. (16), which has the two solutions of eq. (17); the one with S > 0 is taken.
If |Delta0| > sqrt(U1^2 + U2^2), eq. (16) has no solution.

After the orbit is built, the gap over the period shows whether the orbit is admissible:
the paper's Fig. 2a shows a gap below zero on (t1, t2), which means Algorithm No. 1 does
not describe the motion there.

Sign note: eq. (13) as transcribed writes x21s' as sum(alpha lambda e) - sum(alpha A lambda e),
which is x1s' - x2s'; eq. (12) defines x21s = x2s - x1s, and so does this module.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.core.events import LinearFunctional, SearchLimitError, Segment, StepBudget, march
from impactdamper.core.impact_law import impact_pulse
from impactdamper.core.linear import characteristic_roots, forced_amplitudes, mode_shape_ratios
from impactdamper.core.model import FORCED_AMPLITUDE_LIMIT, Model
from impactdamper.core.parameters import RELATIVE_PARAMETERS, Parameters, ScaleMap, most_extreme, require_parameters
from impactdamper.core.validation import check_gap_tol, work_limit_message

__all__ = ["Algorithm1Result", "algorithm1", "unit_pulse_response", "rescale_algorithm1"]

# Sampling of the gap over the period to locate its minimum before refining it.
MIN_GAP_SAMPLES = 512
# Work bound of the negative-gap scan: roots of the gap (crossings, touches) and certified
# search steps over the period. An admissible or inadmissible orbit has a few of each; a gap at
# rounding level for a whole stretch (mu = 1e-300) stepped on for ever.
MAX_SCAN_ROOTS = 1000
MAX_SCAN_STEPS = 200_000


def unit_pulse_response(p: Parameters, model: Model | None = None, modal: bool | None = None) -> np.ndarray:
    """State z(0+) of the T-periodic response to a unit pulse pair at t = 0 mod T, eqs. (6)-(8).

    Parameters
    ----------
    modal : bool, optional
        True: solve the paper's eq. (8) for alpha_j with roots lambda_j and ratios A_j
        (needs simple roots). False: the same conditions (7) in matrix form,
        (I - e^{M T}) z(0+) = (0, 0, 1/m1, -1/m2), valid for any roots. Default: modal where
        the modal form is well conditioned.

    Returns
    -------
    ndarray, shape (4,)
        (x1s, x2s, x1s', x2s') just after the pulse, per unit pulse (m/(N s), 1/kg).
    """
    model = model or Model(p)
    mode = model.free
    if modal is None:
        modal = mode.modal
    T = p.T
    if modal:
        lam = characteristic_roots(p)
        A = mode_shape_ratios(p, lam)
        E = np.exp(lam * T) - 1.0
        lhs = np.array([E, p.m1 * lam * E, A * E, p.m2 * lam * A * E])
        alpha = np.linalg.solve(lhs, np.array([0.0, -1.0, 0.0, 1.0], dtype=complex))
        # Eq. (6) at t = 0+: x1s = sum alpha, x2s = sum alpha A, and their derivatives.
        return np.real(np.array([alpha.sum(), (alpha * A).sum(), (alpha * lam).sum(), (alpha * A * lam).sum()]))
    J = np.array([0.0, 0.0, 1.0 / p.m1, -1.0 / p.m2])
    return np.linalg.solve(np.eye(4) - mode.propagator(T), J)


@dataclass(frozen=True)
class Algorithm1Result:
    """Result of Algorithm No. 1.

    Attributes
    ----------
    exists : bool
        Eq. (16) has a solution with a positive pulse.
    reason : str
        Why not, when it does not exist ("" otherwise).
    eps : float
        Chosen impact phase eps = omega t_y* of eq. (17), rad in [0, 2 pi).
    S : float
        Pulse at each impact, eq. (15), N s.
    candidates : list of (eps, S)
        Both solutions of eq. (17) with their pulses.
    U1, U2, zeta, eps21 : float
        The quantities of eqs. (12), (16), (17).
    velocity : float
        Closing relative velocity before the impact, S/D, m/s.
    min_gap : float
        Smallest interior local minimum of the gap Delta/x_st over the period (how close the
        orbit comes to the stop between impacts; negative if it crosses it); 0 if the gap
        has no interior minimum (its minimum is the impact itself).
    t_min_gap : float
        Where that minimum is, in units of T since the impact; NaN if there is no interior
        minimum.
    negative_gap_intervals : list of (float, float)
        Intervals of time since the impact, in units of T, where the gap is negative.
    """

    p: Parameters = field(repr=False)
    exists: bool
    reason: str = ""
    eps: float = math.nan
    S: float = math.nan
    candidates: tuple = ()
    U1: float = math.nan
    U2: float = math.nan
    zeta: float = math.nan
    eps21: float = math.nan
    velocity: float = math.nan
    min_gap: float = math.nan
    t_min_gap: float = math.nan
    negative_gap_intervals: tuple = ()
    state_after: np.ndarray = field(default=None, repr=False)

    @property
    def impact_phase(self) -> float:
        """Impact time t_y* over T, modulo 1 (absolute time of the forcing P0 sin(omega t))."""
        return (self.eps / (2.0 * math.pi)) % 1.0

    @property
    def t_impact(self) -> float:
        return self.impact_phase * self.p.T

    @property
    def admissible(self) -> bool:
        """The orbit exists and its gap never goes negative."""
        return self.exists and not self.negative_gap_intervals

    def sample(self, tau: np.ndarray) -> np.ndarray:
        """Full states (x1, x2, x1', x2') at times tau since the impact (0 <= tau <= T), s.

        Returns shape tau.shape + (4,); at tau = 0 the state just after the impact."""
        if not self.exists:
            raise ValueError("`algorithm1` found no orbit: nothing to sample")
        model = Model(self.p)
        return Segment(model.free, self.t_impact, self.state_after).state(self.t_impact + np.asarray(tau, dtype=float))

    def to_dict(self) -> dict:
        d = {
            "exists": self.exists,
            "reason": self.reason,
            "eps": self.eps,
            "impact_phase": self.impact_phase if self.exists else None,
            "S": self.S,
            "velocity": self.velocity,
            "candidates": [{"eps": e, "S": s} for e, s in self.candidates],
            "U1": self.U1,
            "U2": self.U2,
            "zeta": self.zeta,
            "eps21": self.eps21,
            "min_gap": self.min_gap,
            "t_min_gap_over_T": self.t_min_gap,
            "admissible": self.admissible,
            "negative_gap_intervals": [list(iv) for iv in self.negative_gap_intervals],
            "parameters": self.p.to_dict(),
        }
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in d.items()}


def algorithm1(p: Parameters, gap_tol: float = 1e-12) -> Algorithm1Result:
    """Algorithm No. 1: the periodic one-impact orbit, eqs. (7)-(8) and (13)-(17).

    Parameters
    ----------
    p : Parameters
    gap_tol : float
        Resolution of the negative-gap search, relative to x_st.

    Returns
    -------
    Algorithm1Result

    Raises
    ------
    TypeError, ValueError
        A bad argument, named; or ``theta`` at an undamped resonance, where the closed form is
        singular (the forced response, or the T-periodic pulse response of eq. 8, unbounded).
    SearchLimitError
        The negative-gap scan exceeded its work bound.

    Results in relative units do not depend on the free scales x_st, m1 and omega (outside
    :data:`impactdamper.core.parameters.NATIVE_SCALES` the same relative problem is solved in the
    reference case's units and converted back).
    """
    p = require_parameters(p)
    gap_tol = check_gap_tol(gap_tol)
    if not p.native_scales():
        q = p.canonical()
        return rescale_algorithm1(algorithm1(q, gap_tol), ScaleMap(q, p))
    try:
        # Overflow and invalid operations are errors here, not warnings and NaN results: the
        # closed form of extreme parameters (N = 1e12, a stiff suppressor) overflowed e^{MT}.
        with np.errstate(over="raise", invalid="raise", divide="raise"):
            return _algorithm1(p, gap_tol)
    except (FloatingPointError, ZeroDivisionError, OverflowError, np.linalg.LinAlgError) as err:
        name = most_extreme(p, RELATIVE_PARAMETERS)
        raise ValueError(
            f"`{name}` = {getattr(p, name)!r} is beyond what Algorithm No. 1's closed form resolves "
            f"({type(err).__name__}: {' '.join(str(err).split())}); allowed are parameters nearer the "
            "reference case (theta = 1, mu = 0.08, N = 0.5, delta1 = delta2 = 0.05)"
        ) from None


def _algorithm1(p: Parameters, gap_tol: float) -> Algorithm1Result:
    """algorithm1 on validated arguments in native scales."""
    model = Model(p)
    _check_pulse_resonance(p, model)
    z0 = unit_pulse_response(p, model)
    zT = model.free.free(p.T, z0)  # just before the next pulse
    x21s_T, dx21s_T = zT[1] - zT[0], zT[3] - zT[2]
    x1p, x2p = forced_amplitudes(p)
    U1 = float(abs(x2p - x1p))
    eps21 = math.atan2((x2p - x1p).imag, (x2p - x1p).real)
    D = impact_pulse(p, 1.0)  # D = m_red (1 + R), eq. (14)
    denom = 1.0 - D * dx21s_T
    if not abs(denom) > 1.0 / FORCED_AMPLITUDE_LIMIT:
        if p.delta1 == 0.0 and p.delta2 == 0.0:
            # Undamped, the T-periodic pulse response is time-symmetric: D x21s'(T) = (1 + R)/2
            # and the denominator is (1 - R)/2 at every theta, so no theta helps.
            raise ValueError(
                f"`R` = {p.R!r} is not allowed with delta1 = delta2 = 0: without damping the denominator "
                f"1 - D x21s'(T) of eq. 15 is (1 - R)/2 = {denom:.3g} at every theta, so Algorithm No. 1's closed "
                "form is singular (no energy is lost anywhere); lower R or add damping (delta1 or delta2 > 0)"
            )
        raise ValueError(
            f"`theta` = {p.theta!r} is not allowed with these parameters: Algorithm No. 1's closed form is "
            f"singular there (the denominator 1 - D x21s'(T) of eq. 15 is {denom:.3g}): move theta"
        )
    U2 = float(D * x21s_T / denom * U1 * p.omega)
    common = dict(p=p, U1=U1, U2=U2, eps21=eps21)
    amplitude = math.hypot(U1, U2)
    rho = p.Delta0 / amplitude
    zeta = math.atan2(U2, U1)
    common["zeta"] = zeta
    if abs(rho) > 1.0:
        return Algorithm1Result(
            exists=False, reason=f"|Delta0|/sqrt(U1^2+U2^2) = {abs(rho):.6g} > 1: eq. (16) has no solution", **common
        )
    candidates = []
    for phi in (math.asin(rho) - zeta, math.pi - math.asin(rho) - zeta):
        eps = (phi - eps21) % (2.0 * math.pi)
        S = D * U1 * p.omega * math.cos(phi) / denom  # eq. (15) with eq. (13) at t = T
        candidates.append((eps, S))
    positive = [c for c in candidates if c[1] > 0.0]
    if not positive:
        return Algorithm1Result(
            exists=False,
            reason="neither root of eq. (17) gives a positive pulse S",
            candidates=tuple(candidates),
            **common,
        )
    candidates = [(float(e), float(s)) for e, s in candidates]
    eps, S = positive[0]
    eps, S = float(eps), float(S)
    t_imp = (eps / (2.0 * math.pi) % 1.0) * p.T
    after = model.free.forced(t_imp) + S * z0
    intervals, (t_min, g_min) = _gap_scan(model, Segment(model.free, t_imp, after), t_imp, gap_tol)
    return Algorithm1Result(
        exists=True,
        eps=eps,
        S=S,
        candidates=tuple(candidates),
        velocity=float(S / D),
        min_gap=g_min / p.x_st,
        t_min_gap=t_min,
        negative_gap_intervals=tuple(intervals),
        state_after=after,
        **common,
    )


def _check_pulse_resonance(p: Parameters, model: Model) -> None:
    """Eq. (8) asks for the T-periodic response to one pulse per period: it does not exist where
    e^{lambda T} = 1 for a root lambda (an undamped natural frequency a multiple of omega)."""
    lam = model.free.roots
    closeness = np.abs(np.exp(lam * p.T) - 1.0)
    j = int(np.argmin(closeness))
    if closeness[j] <= 1.0 / FORCED_AMPLITUDE_LIMIT:
        k = abs(lam[j].imag) / p.omega
        if round(k) == 0:  # a root at zero: the suppressor's spring too soft to bring it back
            raise ValueError(
                f"`N` = {p.N!r} is not allowed with theta = {p.theta!r}: the free suppressor's spring is so soft "
                f"that a root of the free motion is {abs(lam[j]) / p.omega1:.3g} omega1, nearly zero, where the "
                "T-periodic pulse response of Algorithm No. 1 (eq. 8) is unbounded (nothing brings the suppressor "
                "back between impacts); raise N"
            )
        raise ValueError(
            f"`theta` = {p.theta!r} is not allowed with delta1 = {p.delta1!r}, delta2 = {p.delta2!r}: a (nearly) undamped "
            f"natural frequency of the free suppressor, {abs(lam[j].imag) / p.omega1:.9g} omega1, is {k:.6g} times the "
            "forcing frequency, where the T-periodic pulse response of Algorithm No. 1 (eq. 8) is unbounded and its "
            "closed form singular (a resonance of the impacts); add damping (delta1, delta2 > 0) or move theta"
        )


def rescale_algorithm1(r: Algorithm1Result, scales: ScaleMap) -> Algorithm1Result:
    """The same result in ``scales.target``'s units (phases and relative values unchanged).

    The impulse S (eq. 15), the amplitudes U1, U2 (eqs. 12-13), the closing velocity and the
    state after the impact change units; the impact phase and the relative values do not (the
    relative problem is independent of x_st, m1 and omega).

    Parameters
    ----------
    r : Algorithm1Result
    scales : ScaleMap
        From ``r.p``'s units to ``scales.target``'s.
    """
    return dataclasses.replace(
        r,
        p=scales.target,
        S=scales.apply(r.S, "impulse"),
        candidates=tuple((e, scales.apply(s, "impulse")) for e, s in r.candidates),
        U1=scales.apply(r.U1, "length"),
        U2=scales.apply(r.U2, "length"),
        velocity=scales.apply(r.velocity, "velocity"),
        state_after=None if r.state_after is None else scales.full(r.state_after),
    )


def _gap_scan(model: Model, seg: Segment, t_imp: float, gap_tol: float) -> tuple[list, tuple]:
    """Negative-gap intervals over (t_imp, t_imp + T) (in units of T since the impact) and
    the gap's minimum (time over T, value in m)."""
    intervals = _negative_gap_intervals(model, seg, t_imp, gap_tol)
    return [(float(a), float(b)) for a, b in intervals], _gap_minimum(model, seg, t_imp)


def _negative_gap_intervals(model: Model, seg: Segment, t_imp: float, gap_tol: float) -> list:
    """The stretches of (t_imp, t_imp + T) where the gap is negative (beyond the grazing
    resolution), in units of T since the impact: the gap and minus it marched in turn."""
    p = model.p
    T, tol = p.T, gap_tol * p.x_st
    budget = StepBudget(
        MAX_SCAN_STEPS,
        lambda t: work_limit_message(
            p, f"the negative-gap scan of Algorithm No. 1's orbit took more than {MAX_SCAN_STEPS} certified steps"
        ),
    )
    roots = 0
    gap = model.gap
    neg = LinearFunctional(gap.mode, -gap.c, -gap.g0, -gap.d_s)
    intervals = []
    t, fn, sign, departure = t_imp, gap, +1, None
    v0 = seg.y0[2] - seg.y0[3]  # opening relative velocity after the impact = R v
    departure = (1, v0) if v0 > 0 else None
    end = t_imp + T * (1.0 - 1e-9)  # the next impact closes the period
    while True:
        try:
            root, _ = march(seg, fn, t, end, tol, departure, budget)
        except SearchLimitError as err:
            if str(err).startswith("`"):  # the budget's message names a parameter already
                raise
            raise SearchLimitError(work_limit_message(p, str(err))) from None
        roots += 1
        if roots > MAX_SCAN_ROOTS:
            raise SearchLimitError(
                work_limit_message(
                    p, f"the gap of Algorithm No. 1's orbit touches or crosses zero more than {MAX_SCAN_ROOTS} times"
                )
            )
        if root is None:
            if sign < 0:
                intervals.append(((t - t_imp) / T, 1.0))
            break
        t_root, slope = root
        if t_root >= end:
            # Newton's polish moved the root past the search's end: it is the next impact (a
            # coarse gap_tol reaches it early). A negative stretch then lasts to the period's end.
            if sign < 0:
                intervals.append(((t - t_imp) / T, 1.0))
            break
        if t_root <= t:
            # A root at the search's own start is a tangency at
            # rounding level (g and g' both ~0 there), not a crossing. Flipping between the gap
            # and -gap at the same instant looped for ever (gap = -8.848978948812440, the onset
            # of Algorithm No. 1's crossing). Leave the tangency by the curvature instead.
            curvature = float(fn.of_state(t, seg.state(t), 2))
            if curvature > 0.0:  # a touch: stay on this side
                departure = (2, curvature)
                continue
            if curvature == 0.0:  # degenerate: step past by the time resolution
                t, departure = t + 1e-15 * T, None
                continue
        if sign > 0:
            start = t_root
        elif float(model.gap_of(seg.state(0.5 * (start + t_root)))) < -tol:
            intervals.append(((start - t_imp) / T, (t_root - t_imp) / T))
        # else: the gap only touched zero within the grazing resolution; not a crossing.
        fn, sign = (neg, -1) if sign > 0 else (gap, +1)
        departure = (1, -slope) if slope < 0 else None
        if t_root <= t:  # FIX (continued): the function turns down here; leave by its curvature
            departure = (2, -curvature)
        t = t_root
    return intervals


def _gap_minimum(model: Model, seg: Segment, t_imp: float) -> tuple[float, float]:
    """The smallest interior local minimum of the gap over the period after the impact (time
    over T, value in m; 0 at the impact itself if there is none): sampled, then each sampled
    local minimum refined on its bracketing samples."""
    T = model.p.T
    ts = t_imp + T * np.linspace(0.0, 1.0, MIN_GAP_SAMPLES + 1)
    g = model.gap_of(seg.state(ts))
    g[0] = g[-1] = 0.0  # the impacts (rounding aside)
    minima = []
    for k in np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] <= g[2:])) + 1:
        import scipy.optimize  # (loaded on first use: the package import stays light)

        res = scipy.optimize.minimize_scalar(
            lambda s: float(model.gap_of(seg.state(s))),
            bounds=(ts[k - 1], ts[k + 1]),
            method="bounded",
            options={"xatol": 1e-14 * T},
        )
        minima.append((float(res.fun), float((res.x - t_imp) / T)))
    g_min, t_min = min(minima) if minima else (0.0, math.nan)
    return t_min, g_min
