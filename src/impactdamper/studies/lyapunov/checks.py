"""The checks of the compiled Lyapunov spectrum, and its cost, for the stage's record.

Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100. Each check compares the
spectrum (:func:`impactdamper.analysis.lyapunov.lyapunov_spectrum`, the compiled walk: exact
transition matrices, saltation matrices, QR) with another computation. One is independent
(it shares no flow, event or model code with the walk); the others are consistency checks in
the sense of the report's Section 3.6 (they test the walk's saltation matrices and QR, not its
flow or its events, which they share):

* **Benettin on solve_ivp** (independent,
  :func:`impactdamper.studies.lyapunov.independent.independent_check`): the largest exponent
  from two trajectories of :mod:`impactdamper.baselines.benettin_ivp` (its own equations,
  parameter conversion and impact law, DOP853 with event location; no library code), started
  from the walk's last section (4 numbers) after a transient of its own;
* **Floquet multipliers** (consistency: the same flow propagator): at a stable periodic orbit
  every exponent equals log|rho_i| / k per forcing period, rho_i the eigenvalues of the
  monodromy matrix of the orbit solver (:func:`impactdamper.analysis.orbits.solve_orbit`:
  Newton shooting, one product over one cycle), against the walk's weighted average over
  thousands of periods;
* **Benettin's two-trajectory estimate** (consistency: the same event solver): the largest
  exponent from the growth of a small separation between two runs of the solver alone,
  renormalised every period (the stroboscopic map of the same backend: no saltation matrix, no
  tangent), along the same motion and on the next stretch of the attractor;
* **the sum rule** (consistency of the walk's determinants): the exponents' sum per period
  equals the free flow's trace times T plus 2 log R per impact (det of an impact's saltation
  matrix is R^2), the impacts counted by re-running each period from its section;
* **the torus** (:func:`torus_check`): the quasi-periodic motions past the 3/2 cycle's
  Neimark-Sacker point turn per 2 T by about the angle of that cycle's complex multipliers;
* **the window** (:func:`window_check`): one point run with a short and a long window, what
  its label says of each;
* **the two backends** (consistency): the compiled walk against the reference's (Householder
  QR on the reference solver's events) at a periodic and a chaotic point.

Timings (:func:`speed`) are CPU times, minima over repeats: a benchmark, not a result.
"""

from __future__ import annotations

import math
import subprocess
import sys
import time

import numpy as np

from impactdamper.analysis.lyapunov import SIGNIFICANCE, birkhoff_weights, lyapunov_spectrum
from impactdamper.analysis.orbits import solve_orbit
from impactdamper.analysis.solve import simulate
from impactdamper.core.backends import get_backend
from impactdamper.core.parameters import Parameters, state_scale
from impactdamper.core.validation import Tolerances

__all__ = [
    "BENETTIN_EPS",
    "BENETTIN_FLOOR",
    "floquet_check",
    "benettin",
    "benettin_check",
    "sum_rule_check",
    "backends_check",
    "speed",
    "command_wall",
]

# Benettin's separation, relative to (x_st, x_st omega): small enough that the map's second
# derivative adds ~EPS per period (measured 1.3e-6 to 8e-6 at the chaotic points), large enough
# that the rounding of the two states (~1e-15) adds only ~1e-15/EPS = 1e-8 to each period's log.
BENETTIN_EPS = 1e-7
# That rounding floor of Benettin's estimate, bounded (measured at gap -12.7: 3e-8 at EPS 1e-7).
BENETTIN_FLOOR = 1e-6
# Periods skipped at the start of the same-motion comparison, while the separation turns onto
# the leading direction (as the walk's frame does in its warm-up).
ALIGN_PERIODS = 50


def _weighted(x: np.ndarray) -> float:
    return float(birkhoff_weights(len(x)) @ x)


def floquet_check(p: Parameters, run: dict) -> dict:
    """Exponents against log|mu| / k of the orbit solver's stable orbit at ``p`` (``run``: the
    spectrum's run lengths)."""
    o = solve_orbit(p)
    if not (o.solved and o.stable):
        raise ValueError(f"no stable orbit solved at gap {p.gap}: {o.regime}, {o.reason}")
    floquet = np.sort(np.log(np.abs(o.multipliers)) / o.period_multiple)[::-1]
    s = lyapunov_spectrum(p, backend="compiled", **run)
    return {
        "gap": p.gap,
        "k": int(o.period_multiple),
        "z": len(o.impacts),
        "exponents": s.exponents.tolist(),
        "floquet": floquet.tolist(),
        "difference": float(np.max(np.abs(s.exponents - floquet))),
        "label": s.label,
        "backend": s.backend,
    }


def benettin(
    p: Parameters, start: np.ndarray, periods: int, *, along: np.ndarray | None = None, step=None
) -> np.ndarray:
    """Per-period log growth of a separation BENETTIN_EPS (relative units) between two runs of
    the solver alone, renormalised every period.

    ``step(y)``: the state one forcing period on from y (default: the compiled backend's
    stroboscopic map from t = 0). The reference motion is the map's from ``start``, or, with
    ``along`` (shape (periods + 1, 4)), the given section states. Returns shape (periods,)."""
    if step is None:
        strobe = get_backend("compiled")[0].map_step(p, Tolerances())

        def step(y):
            return strobe(y, 1)[0]

    D = state_scale(p)
    d = np.full(4, 0.5)
    y = np.array(start, float)
    out = np.empty(periods)
    for n in range(periods):
        for sign in (1.0, -1.0):  # a perturbation that keeps the gap >= 0 (a motion in contact)
            yb = y + sign * BENETTIN_EPS * D * d
            if p.Delta0 - (yb[1] - yb[0]) >= -1e-12 * p.x_st:
                break
        y_next = along[n + 1] if along is not None else step(y)
        sep = (step(yb) - y_next) / D
        r = float(np.linalg.norm(sep))
        out[n] = math.log(r / BENETTIN_EPS)
        d, y = sep / r, y_next
    return out


def benettin_check(p: Parameters, run: dict) -> dict:
    """The largest exponent against Benettin's estimate: (1) along the same motion (the walk's
    sections as the reference run), the plain means after ALIGN_PERIODS; (2) on the next
    ``periods`` periods of the attractor, the weighted average and its block standard error,
    agreeing within SIGNIFICANCE combined errors plus BENETTIN_FLOOR."""
    s = lyapunov_spectrum(p, backend="compiled", **run)
    same = benettin(p, s.sections[0], s.periods - 1, along=s.sections)
    same_difference = abs(same[ALIGN_PERIODS:].mean() - s.increments[ALIGN_PERIODS:-1, 0].mean())
    strobe = get_backend("compiled")[0].map_step(p, Tolerances())
    growth = benettin(p, strobe(s.sections[-1], 1)[0], s.periods)
    blocks = np.array([_weighted(b) for b in np.split(growth, s.blocks)])
    lam, err = _weighted(growth), float(blocks.std(ddof=1) / math.sqrt(s.blocks))
    combined = math.hypot(err, s.errors[0])
    bound = SIGNIFICANCE * combined + BENETTIN_FLOOR
    return {
        "gap": p.gap,
        "label": s.label,
        "exponent": float(s.exponents[0]),
        "error": float(s.errors[0]),
        "benettin": lam,
        "benettin_error": err,
        "difference": abs(lam - float(s.exponents[0])),
        "bound": bound,
        "agrees": abs(lam - float(s.exponents[0])) <= bound,
        "same_motion_difference": same_difference,
        "captures": s.captures,
    }


def sum_rule_check(p: Parameters, run: dict) -> dict:
    """The sum of the exponents per period against tr(M_free) T + 2 log R x (impacts in the
    period), the impacts counted by running each period again from its section; motion without
    persistent contact (the 4-volume a capture annihilates has no such closed form)."""
    s = lyapunov_spectrum(p, backend="compiled", **run)
    if s.captures or s.dimension != 4:
        raise ValueError(f"gap {p.gap}: the sum rule holds for motion without persistent contact")
    trace = -((p.k1 + p.k2) / p.m1 + p.k2 / p.m2) * p.T
    closed = np.empty(s.periods)
    for n, y in enumerate(s.sections):
        impacts = sum(e.kind == "impact" for e in simulate(p, s.t_section + p.T, s.t_section, y).events)
        closed[n] = trace + 2.0 * math.log(p.R) * impacts
    sums = s.increments.sum(axis=1)
    return {
        "gap": p.gap,
        "label": s.label,
        "sum": float(s.exponents.sum()),
        "closed_form": _weighted(closed),
        "per_period_residual": float(np.max(np.abs(sums - closed) / np.abs(closed))),
        "total_residual": float(abs(sums.sum() - closed.sum()) / abs(closed.sum())),
        "impacts_per_period": s.impacts / s.periods,
    }


def backends_check(p: Parameters, run: dict) -> dict:
    """The compiled walk against the reference's along the same motion: the largest difference
    of the exponents, and of each against the other's SIGNIFICANCE combined errors."""
    c = lyapunov_spectrum(p, backend="compiled", **run)
    r = lyapunov_spectrum(p, backend="python", **run)
    finite = np.isfinite(r.exponents) & np.isfinite(c.exponents)
    diff = np.abs(c.exponents[finite] - r.exponents[finite])
    combined = np.hypot(c.errors[finite], r.errors[finite])
    return {
        "gap": p.gap,
        "labels": [c.label, r.label],
        "difference": float(diff.max()),
        "within_errors": bool(np.all(diff <= SIGNIFICANCE * combined)),
        "largest_in_errors": float(np.max(diff / combined)),
        "same_events": (c.impacts, c.captures, c.liftoffs) == (r.impacts, r.captures, r.liftoffs),
    }


def window_check(p: Parameters, runs) -> list[dict]:
    """One point's spectrum from the paper's step 1 with each (transient, periods) of ``runs``:
    what the label says of the window it averaged (its halves, the cycle it settled onto)."""
    out = []
    for transient, periods in runs:
        d = lyapunov_spectrum(p, backend="compiled", transient=int(transient), periods=int(periods)).to_dict()
        keep = ("label", "halves", "half_errors", "settled_period", "settled_since", "window", "warmup")
        out.append(
            {"gap": p.gap, "transient": int(transient), "periods": int(periods), "exponent": d["exponents"][0],
             "error": d["errors"][0], **{k: d[k] for k in keep}}
        )  # fmt: skip
    return out


def _rotation_per_cycle(sections: np.ndarray, k: int) -> float:
    """The mean angle (rad, >= 0) by which a motion's sections (relative units, one per forcing
    period) turn per k periods about their centre, in the plane of their two main directions:
    on a torus born at a Neimark-Sacker point of a k T cycle, near the angle of the complex pair
    of that cycle's multipliers. The mean over the k interleaved series of every k-th section."""
    turns = []
    for offset in range(k):
        z = sections[offset::k] - sections[offset::k].mean(axis=0)
        plane = np.linalg.svd(z, full_matrices=False)[2][:2]
        w = z @ plane.T
        angle = np.unwrap(np.arctan2(w[:, 1], w[:, 0]))
        turns.append(abs(angle[-1] - angle[0]) / (len(angle) - 1))
    return float(np.mean(turns))


def torus_check(orbit_gap: float, gaps, transient: int, base: Parameters) -> dict:
    """The quasi-periodic motions at ``gaps`` against the stable cycle at ``orbit_gap`` before its
    Neimark-Sacker point: each motion's turn per k T (:func:`rotation_per_cycle`, after
    ``transient`` periods, the default window) against the angle of the cycle's complex pair of
    multipliers (the orbit solver's)."""
    o = solve_orbit(base.replace(gap=float(orbit_gap)))
    if not (o.solved and o.stable):
        raise ValueError(f"no stable orbit solved at gap {orbit_gap}: {o.regime}, {o.reason}")
    complex_pair = o.multipliers[np.abs(np.imag(o.multipliers)) > 0]
    angle = float(np.max(np.abs(np.angle(complex_pair))))
    rows = []
    for gap in gaps:
        p = base.replace(gap=float(gap))
        s = lyapunov_spectrum(p, backend="compiled", transient=int(transient))
        turn = _rotation_per_cycle(s.sections / state_scale(p), int(o.period_multiple))
        rows.append({"gap": p.gap, "label": s.label, "rotation": turn, "difference": abs(turn - angle)})
    return {"orbit_gap": float(orbit_gap), "k": int(o.period_multiple), "angle": angle, "modulus": float(np.max(np.abs(complex_pair))), "motions": rows}  # fmt: skip


def _cpu(call, repeats: int) -> float:
    """The least CPU time of ``repeats`` calls, s."""
    best = math.inf
    for _ in range(repeats):
        t = time.process_time()
        call()
        best = min(best, time.process_time() - t)
    return best


def speed(gaps, periods: int, repeats: int, reference_repeats: int = 1) -> list[dict]:
    """CPU time of one point's spectrum (``periods`` averaged after no transient and no warm-up,
    from the paper's step 1) by each backend, ms; the compiled one after its kernels are loaded."""
    get_backend("compiled")[0].warm_up()
    out = []
    for gap in gaps:
        p = Parameters().replace(gap=float(gap))
        run = dict(periods=periods, transient=0, warmup=0)
        s = lyapunov_spectrum(p, backend="compiled", **run)
        compiled = _cpu(lambda: lyapunov_spectrum(p, backend="compiled", **run), repeats)
        reference = _cpu(lambda: lyapunov_spectrum(p, backend="python", **run), reference_repeats)
        out.append(
            {
                "gap": p.gap,
                "periods": periods,
                "label": s.label,
                "impacts_per_period": s.impacts / s.periods,
                "compiled_ms": 1e3 * compiled,
                "python_ms": 1e3 * reference,
                "speedup": reference / compiled,
            }
        )
    return out


def command_wall(args: list[str], repeats: int) -> float:
    """The least wall time of ``python -m impactdamper lyapunov ARGS --json`` (a new process
    each time, numba's cache warm), s."""
    best = math.inf
    for _ in range(repeats):
        t = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "impactdamper", "lyapunov", *args, "--json"], check=True, capture_output=True
        )
        best = min(best, time.perf_counter() - t)
    return best
