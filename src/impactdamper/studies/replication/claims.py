"""The paper's claims about its Fig. 2, and the aligned comparison of two settled cycles.

Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100, say of
the reference case (Delta0/x_st = -5.8, the prose around the paper's Fig. 2):

* **(a)** Algorithm No. 1 (eqs. 7-17) gives an orbit whose gap is negative on an interval
  (t1, t2) (the paper's Fig. 2a);
* **(b)** Algorithm No. 2, run from its step 1 until the motion settles, gives T_c = 2T with
  three impacts t1, t2, t3 per cycle (the paper's Fig. 2b).

:func:`compare_cycles` compares two settled cycles of the same motion computed by different
methods (the exact solver and an independent integrator): the cycles are aligned by forcing
phase (the same period multiple k, impacts matched by t/T modulo k, over the k shifts by a
whole period), and "agree" means the measured time and velocity differences are below stated
tolerances. Where along a parameter the claims hold is the claims stage's
(:mod:`impactdamper.studies.claims.search`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field

__all__ = [
    "CLAIM_B_PERIOD_MULTIPLE",
    "CLAIM_B_IMPACTS",
    "claim_a",
    "claim_b",
    "compare_cycles",
]

# Claim (b): the paper's Fig. 2b motion, T_c = 2T with three impacts per cycle.
CLAIM_B_PERIOD_MULTIPLE = 2
CLAIM_B_IMPACTS = 3


def claim_a(alg1) -> bool:
    """Claim (a) for an :class:`~impactdamper.Algorithm1Result`: the orbit exists (eq. 17 has
    a root) and its gap is negative somewhere between impacts."""
    return bool(alg1.exists and alg1.negative_gap_intervals)


def claim_b(steady) -> bool:
    """Claim (b) for a :class:`~impactdamper.SteadyState`: T_c = 2T, three impacts, no
    persistent contact in the cycle."""
    return bool(
        steady.regime == "multi_impact"
        and steady.period_multiple == CLAIM_B_PERIOD_MULTIPLE
        and steady.impacts_per_cycle == CLAIM_B_IMPACTS
    )


# --- the aligned cross-check of two settled cycles ------------------------------------------
@dataclass(frozen=True)
class _CycleComparison:
    """Two settled cycles compared impact by impact, aligned by forcing phase.

    Attributes
    ----------
    period_multiple : (int, int)
        k of each cycle (T_c = k T; 0 when a motion did not settle).
    impacts : (int, int)
        Impacts per cycle of each.
    matched : int
        Impacts paired one to one (all of them when the cycles agree).
    shift_periods : int
        Whole periods added to the first cycle's times to align it with the second.
    max_time_difference_over_T : float
        Largest |t_a - t_b|/T over the pairs (inf when the cycles cannot be paired).
    max_velocity_difference_rel : float
        Largest |v_a - v_b|/(x_st omega) of the closing velocities (inf when not paired).
    time_tol, velocity_tol : float
        The tolerances "agree" is measured against.
    agree : bool
        Same k, same number of impacts, every impact paired, both differences within tolerance.
    reason : str
        Why they do not agree ("" when they do).
    """

    period_multiple: tuple
    impacts: tuple
    matched: int
    shift_periods: int
    max_time_difference_over_T: float
    max_velocity_difference_rel: float
    time_tol: float
    velocity_tol: float
    agree: bool
    reason: str
    pairs: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def _circular(d: float, k: int) -> float:
    """d modulo k folded into [-k/2, k/2)."""
    return (d + 0.5 * k) % k - 0.5 * k


def compare_cycles(
    a: Sequence, k_a: int, b: Sequence, k_b: int, T: float, velocity_scale: float, time_tol: float, velocity_tol: float
) -> _CycleComparison:
    """Compare settled cycle ``a`` (impacts with ``.t`` in s and ``.velocity`` in m/s, or
    ``(t, velocity)`` pairs) with cycle ``b``.

    The two runs may use different clocks that differ by whole forcing periods (the exact
    solver rebases its clock, and describes the cycle on a fresh run), so an impact is placed
    by u = t/T modulo k, its forcing phase within the cycle. For each shift j = 0..k-1 the
    impacts of ``a`` at u + j are paired with the nearest impacts of ``b``; the shift with the
    smallest largest difference is kept. A pairing that is not one to one, a different k or a
    different number of impacts is a disagreement, never compared by counts alone.

    Parameters
    ----------
    a, b : sequence of impacts, each ``.t``/``.velocity`` or ``(t, velocity)``
    k_a, k_b : int
        Period multiples (T_c = k T) of the two cycles.
    T : float
        Forcing period, s.
    velocity_scale : float
        x_st omega, m/s: velocity differences are relative to it.
    time_tol : float
        Largest time difference that agrees, units of T.
    velocity_tol : float
        Largest velocity difference that agrees, relative to ``velocity_scale``.
    """
    _check_positive(T=T, velocity_scale=velocity_scale, time_tol=time_tol, velocity_tol=velocity_tol)
    ta, tb = _time_velocity(a), _time_velocity(b)
    counts, ks = (len(ta), len(tb)), (int(k_a), int(k_b))

    def fail(reason: str) -> _CycleComparison:
        return _CycleComparison(ks, counts, 0, 0, math.inf, math.inf, time_tol, velocity_tol, False, reason)

    if k_a < 1 or k_b < 1:
        return fail("a motion did not settle (k = 0)")
    if k_a != k_b:
        return fail(f"different period multiples: k = {k_a} and {k_b}")
    if not ta and not tb:
        return _CycleComparison(ks, counts, 0, 0, 0.0, 0.0, time_tol, velocity_tol, True, "", [])
    k = k_a
    ua = [((t / T) % k, v) for t, v in ta]
    ub = [((t / T) % k, v) for t, v in tb]
    best = _best_shift(ua, ub, k, velocity_scale)
    if counts[0] != counts[1]:
        # Report how far apart the paired ones are, but a missing impact never agrees.
        extra = f"; the {min(counts)} paired differ by up to {best[0]:.1e} T" if best else ""
        return fail(f"different impact counts: {counts[0]} and {counts[1]} per cycle{extra}")
    if best is None:
        return fail("the impacts cannot be paired one to one")
    worst_t, j, pairs = best
    worst_v = max(p[1] for p in pairs)
    ok = worst_t <= time_tol and worst_v <= velocity_tol
    reason = "" if ok else _disagreement(worst_t, worst_v, time_tol, velocity_tol)
    return _CycleComparison(
        ks, counts, len(pairs), j, worst_t, worst_v, time_tol, velocity_tol, ok, reason, [list(p) for p in pairs]
    )


def _check_positive(**values: float) -> None:
    """Raises ValueError naming the first of ``values`` that is not a positive finite number."""
    for name, v in values.items():
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"`{name}` = {v!r} is not allowed: must be a positive finite number")


def _time_velocity(impacts: Sequence) -> list[tuple[float, float]]:
    """(t, velocity) of each impact, given as ``.t``/``.velocity`` or as a pair."""
    return [
        (float(i[0]), float(i[1])) if isinstance(i, (tuple, list)) else (float(i.t), float(i.velocity)) for i in impacts
    ]


def _best_shift(ua: list, ub: list, k: int, velocity_scale: float):
    """The shift j = 0..k-1 of the phases ``ua`` (u = t/T mod k, velocity) that pairs each
    impact of ``a`` one to one with the nearest of ``ub`` with the smallest largest phase
    difference: (that difference, j, [(phase difference, relative velocity difference)]), or
    None if no shift pairs them one to one."""
    best = None
    for j in range(k):
        pairs, used = [], set()
        for u, v in ua:
            m = min(range(len(ub)), key=lambda i: abs(_circular(ub[i][0] - (u + j), k))) if ub else None
            if m is None or m in used:
                pairs = None
                break
            used.add(m)
            pairs.append((abs(_circular(ub[m][0] - (u + j), k)), abs(ub[m][1] - v) / velocity_scale))
        if pairs is None:
            continue
        worst = max(p[0] for p in pairs)
        if best is None or worst < best[0]:
            best = (worst, j, pairs)
    return best


def _disagreement(worst_t: float, worst_v: float, time_tol: float, velocity_tol: float) -> str:
    """Why paired cycles disagree: the time difference if it is too large, else the velocity's."""
    if worst_t > time_tol:
        return f"time difference {worst_t:.1e} T > {time_tol:.0e}"
    return f"velocity difference {worst_v:.1e} > {velocity_tol:.0e}"
