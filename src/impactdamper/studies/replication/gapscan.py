"""Where the behaviour of the paper's Fig. 2 occurs: Delta0/x_st scanned with the other
parameters as stated (Timofeev, Lyuminarskiy & Lyuminarskiy 2019,
DOI 10.18698/0236-3941-2019-1-90-100). ``workflow/scripts/gap_scan.py`` runs it and writes
the records.

The paper claims, at Delta0/x_st = -5.8: (a) Algorithm No. 1 gives a gap below zero on
(t1, t2) (Fig. 2a); (b) Algorithm No. 2 gives T_c = 2T with three impacts per cycle (Fig. 2b).
The scan

1. evaluates (a) on a fine grid (Algorithm No. 1 is closed-form) and (b) on a coarser grid
   (Algorithm No. 2 from the paper's step 1, run until settled, by the compiled solver), over
   the config's window;
2. bisects every end of a range where a claim holds to ``bisect_tol`` (Algorithm No. 1's to
   ``ALG1_BISECT_TOL``); a range reaching the window's edge is reported open there;
3. intersects the ranges;
4. solves the cycle of each common range directly (Newton shooting, :mod:`impactdamper.analysis.orbits`)
   and continues it in Delta0/x_st to where it stops being admissible and stable: the
   Floquet multipliers name the bifurcation at each end (the simulation slows down near a
   bifurcation, so its own ends lie slightly inside, and where exactly depends on its
   tolerances);
   then picks the located case: the grid point where both claims hold closest to the stated
   gap, at least ``located_margin`` inside the orbit's stable range (away from the
   bifurcations, where the settled motion converges slowly);
5. cross-checks the ends with the independent integrators: Algorithm No. 1's orbit is
   re-integrated by ``solve_ivp`` just inside and outside each end of (a); Algorithm No. 2
   is rerun by :func:`impactdamper.baselines.ivp.simulate_ivp` at the simulation's bisection
   brackets of (b) and just beyond the orbit's stability boundary.

Deviation from the paper: the paper gives no such scan; the ranges of (b) are for the
paper's step-1 initial state (other initial states may settle elsewhere where motions
coexist), and an end of (b) is where the settled-motion test (``settle_tol`` within
``max_periods``) still recognises T_c = 2T.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from impactdamper.analysis.parallel import map_tasks
from impactdamper.studies.replication import cases as rep
from impactdamper.studies.replication import crosscheck as xc
from impactdamper.studies.config import parameters

__all__ = [
    "ALG1_BISECT_TOL",
    "ALG1_CHECK_OFFSET",
    "ORBIT_CHECK_OFFSET",
    "ORBIT_STEP",
    "ORBIT_BISECT_TOL",
    "orbit_range",
    "end_checks",
    "locate",
    "count_end_checks",
]

# Algorithm No. 1 costs milliseconds: its range ends are bisected to near rounding.
ALG1_BISECT_TOL = 1e-9
# Offsets of the independent checks from an end of claim (a)'s range, and beyond the stability
# boundary of the directly solved orbit (claim (b)), in Delta0/x_st: far enough from the
# bifurcation that the motion there settles (or visibly does not) within max_periods.
ALG1_CHECK_OFFSET = 1e-3
ORBIT_CHECK_OFFSET = 1e-2
# Continuation of the located case's orbit in Delta0/x_st: step, and resolution of its ends.
ORBIT_STEP = 0.01
ORBIT_BISECT_TOL = 1e-6


def _alg2_row(args) -> dict:
    """Both claims at one gap (for the process pool)."""
    base, solver, g = args
    p = parameters(dict(base, gap=float(g)))
    a = rep.run_alg1(p, solver)
    s = rep.run_steady(p, solver)
    iv = a.negative_gap_intervals[0] if a.negative_gap_intervals else (None, None)
    row = {
        # Empty where the orbit does not exist or its gap has no interior minimum (it only
        # rises from the impact and falls to the next one): not a gap that touches zero.
        "gap": float(g),
        "alg1_exists": a.exists,
        "alg1_min_gap": a.min_gap if a.exists and math.isfinite(a.t_min_gap) else None,
        "alg1_t1": iv[0],
        "alg1_t2": iv[1],
        "claim_a": rep.claim_a(a),
        "alg2_regime": s.regime,
        "alg2_period_multiple": s.period_multiple,
        "alg2_impacts_per_cycle": s.impacts_per_cycle,
        "alg2_periods": s.periods,
        "claim_b": rep.claim_b(s),
    }
    row["both"] = row["claim_a"] and row["claim_b"]
    return row


def _orbit_ok(o) -> bool:
    """The 2T cycle with three impacts, admissible and stable (claim (b)'s motion)."""
    return bool(
        o.admissible
        and o.stable
        and o.period_multiple == rep.CLAIM_B_PERIOD_MULTIPLE
        and o.impacts_per_cycle == rep.CLAIM_B_IMPACTS
    )


def _bifurcation(o) -> str:
    """What ends the stable branch, read from the first orbit outside it."""
    if o is None:
        return "the orbit is lost (Newton shooting does not converge)"
    if not o.admissible:
        return "the orbit becomes inadmissible: " + o.reason
    if o.impacts_per_cycle != rep.CLAIM_B_IMPACTS:
        return f"the orbit changes its impact count to {o.impacts_per_cycle}"
    mu = complex(o.multipliers[0])
    if abs(mu.imag) > 1e-9 * abs(mu):
        return (
            f"Neimark-Sacker: a complex pair of Floquet multipliers leaves the unit circle "
            f"(arg mu = {math.degrees(abs(math.atan2(mu.imag, mu.real))):.1f} deg)"
        )
    if mu.real < 0:
        return "period doubling: a Floquet multiplier leaves the unit circle through -1"
    return "a real Floquet multiplier leaves the unit circle through +1"


def orbit_range(p, solver: dict, lo: float, hi: float) -> dict:
    """Where the located case's cycle (T_c = 2T, three impacts) exists, is admissible and is
    stable: the cycle is solved directly (Newton shooting with the exact flow,
    :mod:`impactdamper.analysis.orbits`), continued in Delta0/x_st in steps of ``ORBIT_STEP`` until it
    fails, and each end bisected to ``ORBIT_BISECT_TOL``; the Floquet multipliers say which
    bifurcation ends it. An independent method for the ends of claim (b)'s range: unlike the
    simulation, it does not slow down near a bifurcation."""
    from impactdamper.analysis.orbits import OrbitError, orbit_from_cycle, solve_orbit

    tol = rep.solver_options(solver)["tolerances"]
    seed = solve_orbit(p, seed=rep.run_steady(p, solver), tolerances=tol)
    if not _orbit_ok(seed):
        return {"found": False, "reason": "the located case's settled cycle did not solve to a stable orbit"}

    def solve(g, prev):
        try:
            return orbit_from_cycle(
                p.replace(gap=float(g)), rep.CLAIM_B_PERIOD_MULTIPLE, prev.times, prev.states_after, tolerances=tol
            )
        except OrbitError:
            return None

    out = {
        "found": True,
        "seed_gap": p.gap,
        "step": ORBIT_STEP,
        "bisect_tol": ORBIT_BISECT_TOL,
        "seed_multipliers_abs": [abs(complex(m)) for m in seed.multipliers],
    }
    branch = [(p.gap, seed.spectral_radius)]
    for side, direction, limit in (("lo", -1.0, lo), ("hi", 1.0, hi)):
        prev, g_prev = seed, p.gap
        while True:
            g = g_prev + direction * ORBIT_STEP
            if (g - limit) * direction > 0:
                out[side], out[side + "_open"], out[side + "_bifurcation"] = g_prev, True, "window edge"
                break
            o = solve(g, prev)
            if o is not None and _orbit_ok(o):
                prev, g_prev = o, g
                branch.append((g, o.spectral_radius))
                continue
            g_in, g_out = g_prev, g
            while abs(g_out - g_in) > ORBIT_BISECT_TOL:
                mid = 0.5 * (g_in + g_out)
                om = solve(mid, prev)
                if om is not None and _orbit_ok(om):
                    prev, g_in = om, mid
                else:
                    g_out = mid
            outside = solve(g_out, prev)
            out[side] = 0.5 * (g_in + g_out)
            out[side + "_open"] = False
            out[side + "_bracket"] = [g_in, g_out]
            out[side + "_bifurcation"] = _bifurcation(outside)
            out[side + "_spectral_radius_inside"] = prev.spectral_radius
            out[side + "_spectral_radius_outside"] = outside.spectral_radius if outside is not None else None
            break
    # Largest multiplier modulus along the branch (the simulation settles like rho^n per cycle).
    out["branch"] = [[g, r] for g, r in sorted(branch)]
    return out


def end_checks(
    base: dict, solver: dict, verdict: dict, iv: dict, ranges_a: list, orbit: dict, g_loc: float, workers: int = 1
) -> list:
    """The ends of the located range, checked by the independent integrators.

    * Claim (a)'s ends (Algorithm No. 1): ``solve_ivp`` re-integrates the orbit
      ``ALG1_CHECK_OFFSET`` inside and outside each end and reads the gap's sign.
    * Claim (b)'s ends (Algorithm No. 2): ``simulate_ivp`` reruns the motion from the paper's
      step 1 at the inner bisection bracket of the simulation's end and ``ORBIT_CHECK_OFFSET``
      beyond the stability boundary of the directly solved orbit. (Between the two a Floquet
      multiplier is within ~1 % of the unit circle, the motion settles too slowly for
      ``max_periods`` and the verdict depends on the tolerances: no check is made there.)

    ``agree``: both methods give the same claim verdict and, measured, the same motion: for
    (a) the negative-gap interval ends within ``crosscheck_time_tol`` and the periodicity
    residual within ``crosscheck_residual_tol``; for (b) the same T_c and, where both settle,
    the cycles aligned by forcing phase within ``crosscheck_time_tol`` (T) and
    ``crosscheck_velocity_tol``. ``basis`` states the numbers the verdict rests on. The checks
    are independent of each other: with ``workers`` > 1 they run in a process pool (the slow
    ones integrate thousands of periods), in the same order.
    """
    jobs = []
    ra = next((r for r in ranges_a if r["lo"] <= g_loc <= r["hi"]), None)
    for side, sign in (("lo", 1.0), ("hi", -1.0)):
        if ra is not None and not ra[side + "_open"]:
            for role, g in (
                ("inside", ra[side] + sign * ALG1_CHECK_OFFSET),
                ("outside", ra[side] - sign * ALG1_CHECK_OFFSET),
            ):
                jobs.append((base, solver, verdict, "a", side, role, g))
    rb = iv  # the located case's common range
    for side, sign in (("lo", 1.0), ("hi", -1.0)):
        points = []
        if rb[side + "_claim"] == "b" and rb[side + "_bracket"] is not None:
            points.append(("inside the simulation's end", rb[side + "_bracket"][0]))
        if orbit.get("found") and not orbit.get(side + "_open", True):
            points.append(("beyond the orbit's stability boundary", orbit[side] - sign * ORBIT_CHECK_OFFSET))
        for role, g in points:
            jobs.append((base, solver, verdict, "b", side, role, g))
    checks = map_tasks(_end_check, jobs, workers)
    for c in checks:
        same = c["exact"] == c["independent"]
        if c["claim"] == "a":
            c["agree"] = same and c["comparison"]["agree"]
        elif c["exact_period_multiple"] == 0 and c["independent_period_multiple"] == 0:
            c["agree"] = same  # neither settles: no cycle to compare (basis: both section mismatches)
        else:
            c["agree"] = same and c["details"]["agree"]
    return checks


def _end_check(args) -> dict:
    """One check of :func:`end_checks` (for the process pool): (base, solver, verdict, claim
    ``a`` or ``b``, side, role, gap)."""
    base, solver, verdict, claim, side, role, g = args
    if claim == "a":
        a = rep.run_alg1(parameters(dict(base, gap=g)), solver)
        ivp = xc.alg1_ivp(a, **xc.ivp_options(verdict)) if a.exists else {"claim_a": False, "reason": "no orbit"}
        cmp = xc.compare_alg1(a, ivp, float(verdict["crosscheck_time_tol"]), float(verdict["crosscheck_residual_tol"]))
        return {
            "claim": "a",
            "end": side,
            "role": role,
            "gap": g,
            "exact": rep.claim_a(a),
            "independent": ivp["claim_a"],
            "details": ivp,
            "comparison": cmp,
            "basis": _alg1_basis(cmp),
        }
    p = parameters(dict(base, gap=g))
    s = rep.run_steady(p, solver)
    ivp = xc.alg2_crosscheck(p, s, verdict, solver)
    return {
        "claim": "b",
        "end": side,
        "role": role,
        "gap": g,
        "exact": rep.claim_b(s),
        "exact_regime": s.regime,
        "exact_period_multiple": s.period_multiple,
        "exact_periods": s.periods,
        "exact_residual": s.residual,
        "independent": ivp["claim_b"],
        "independent_period_multiple": ivp["period_multiple"],
        "details": ivp,
        "basis": _alg2_basis(s, ivp),
    }


def _alg1_basis(cmp: dict) -> str:
    if cmp["periodicity_residual"] is None:
        return "no orbit by either method"
    return (
        f"interval ends differ by {cmp['max_interval_end_difference_over_T']:.1e} T "
        f"(tol {cmp['time_tol']:.0e}); periodicity residual {cmp['periodicity_residual']:.1e} "
        f"(tol {cmp['residual_tol']:.0e})"
    )


def _alg2_basis(s, ivp: dict) -> str:
    if s.period_multiple == 0 and ivp["period_multiple"] == 0:
        return (
            f"neither settles: section mismatch {s.residual:.1e} (exact, after {s.periods} T) and "
            f"{ivp['section_mismatch']:.1e} (solve_ivp), both above the settling tolerances"
        )
    c = ivp["cycle_comparison"]
    if not math.isfinite(c["max_time_difference_over_T"]):
        return "cycles differ: " + c["reason"]
    return (
        f"aligned cycles differ by {c['max_time_difference_over_T']:.1e} T (tol {c['time_tol']:.0e}) and "
        f"{c['max_velocity_difference_rel']:.1e} in velocity (tol {c['velocity_tol']:.0e})"
    )


def locate(reference: dict, solver: dict, verdict: dict, workers: int = 1) -> tuple[list[dict], dict]:
    """Scan Delta0/x_st over the config's ``verdict`` window for the paper's two claims and
    locate the case where both hold (steps 1-5 of the module docstring).

    Returns
    -------
    rows : list of dict
        The Algorithm No. 2 grid with both claims (one row per gap).
    result : dict
        The ranges, their ends with brackets, the overlap, the located case, the directly
        solved orbit's range and the cross-checks.
    """
    lo, hi = float(verdict["gap_min"]), float(verdict["gap_max"])
    if not lo < hi:
        raise ValueError(f"`verdict.gap_min` = {lo!r} is not allowed: must be < `verdict.gap_max` = {hi!r}")
    base = parameters(reference).to_dict()
    stated_gap = base["gap"]

    def alg1_pred(g: float) -> bool:
        return rep.claim_a(rep.run_alg1(parameters(dict(base, gap=g)), solver))

    def alg2_pred(g: float) -> bool:
        return rep.claim_b(rep.run_steady(parameters(dict(base, gap=g)), solver))

    # (a): fine grid, closed form.
    g1 = rep.grid(lo, hi, float(verdict["alg1_gap_step"]))
    flags1 = [alg1_pred(float(g)) for g in g1]
    ranges_a = rep.ranges(g1, flags1, alg1_pred, ALG1_BISECT_TOL)
    probe = rep.run_alg1(parameters(base), solver)
    existence_limit = math.hypot(probe.U1, probe.U2) / base["x_st"]  # |Delta0|/x_st beyond which eq. (16) has no root

    # (b) and the table: the coarse grid, in parallel (every point is independent).
    g2 = rep.grid(lo, hi, float(verdict["gap_step"]))
    jobs = [(base, solver, float(g)) for g in g2]
    rows = map_tasks(_alg2_row, jobs, workers)
    ranges_b = rep.ranges(g2, [r["claim_b"] for r in rows], alg2_pred, float(verdict["bisect_tol"]))
    both = rep.overlap(ranges_a, ranges_b)

    # The located case, inside the directly solved orbit's stable range (step 4).
    margin = float(verdict["located_margin"])
    g_loc, k_loc, orbits = _located_case(base, solver, verdict, rows, both)
    iv, orbit = both[k_loc], orbits[k_loc]
    rule = (
        f"the grid point (step {verdict['gap_step']}) closest to the stated Delta0/x_st = {stated_gap:g} "
        f"where both claims hold, at least {margin:g} inside the stable range of the directly solved "
        f"T_c = 2T orbit"
    )

    # Independent checks of the ends of the located case's range.
    checks = end_checks(base, solver, verdict, iv, ranges_a, orbit, g_loc, workers)

    result = {
        "paper": rep.PAPER,
        "window": {
            "gap_min": lo,
            "gap_max": hi,
            "alg1_gap_step": float(verdict["alg1_gap_step"]),
            "alg2_gap_step": float(verdict["gap_step"]),
            "alg1_bisect_tol": ALG1_BISECT_TOL,
            "alg2_bisect_tol": float(verdict["bisect_tol"]),
            "located_margin": margin,
        },
        "stated_gap": stated_gap,
        "alg1_existence_limit": -existence_limit,
        "claim_a_ranges": ranges_a,
        "claim_b_ranges": ranges_b,
        "both_ranges": both,
        "located": {"gap": g_loc, "range": [iv["lo"], iv["hi"]], "rule": rule, "parameters": dict(base, gap=g_loc)},
        "orbit_range": orbit,
        "end_checks": checks,
    }
    return rows, result


def _located_case(base: dict, solver: dict, verdict: dict, rows: list[dict], both: list[dict]) -> tuple:
    """The located case among the Algorithm No. 2 grid's ``rows`` (step 4 of the module
    docstring): (its gap, the index of its common range in ``both``, each common range's orbit
    range).

    The simulation's range ends sit next to bifurcations, where the settled motion converges
    slowly and its classification is fragile (it moves with the solver's rounding); the directly
    solved orbit's stability range does not. So each common range gets its orbit range (seeded at
    the grid point nearest the range's middle), and the located case is a grid point where the
    simulation shows both claims, ``located_margin`` inside the orbit's stable range (inside the
    common range where there is no orbit range), the closest to the stated gap.
    """
    lo, hi = float(verdict["gap_min"]), float(verdict["gap_max"])
    stated_gap = base["gap"]
    margin = float(verdict["located_margin"])
    candidates, orbits = [], []
    for k, iv in enumerate(both):
        inside = [r["gap"] for r in rows if r["both"] and iv["lo"] <= r["gap"] <= iv["hi"]]
        if not inside:
            orbits.append({"found": False, "reason": "no grid point inside"})
            continue
        seed = min(inside, key=lambda g: (abs(g - 0.5 * (iv["lo"] + iv["hi"])), g))
        orbit = orbit_range(parameters(dict(base, gap=seed)), solver, lo, hi)
        orbits.append(orbit)
        o_lo, o_hi = (orbit["lo"], orbit["hi"]) if orbit.get("found") else (iv["lo"], iv["hi"])
        for g in inside:
            if o_lo + margin <= g <= o_hi - margin:
                candidates.append((abs(g - stated_gap), -g, g, k))
    if not candidates:
        raise ValueError(
            f"no grid point of `verdict.gap_min`..`verdict.gap_max` = {lo}..{hi} shows both claims "
            f"at least `verdict.located_margin` = {margin} inside their range: widen the window "
            f"or refine `verdict.gap_step`"
        )
    _, _, g_loc, k_loc = min(candidates)
    return g_loc, k_loc, orbits


def count_end_checks(checks: Sequence[dict]) -> dict:
    """The located range's end checks (:func:`end_checks`) counted
    by what they rest on.

    Returns
    -------
    dict
        ``checks``; ``compared_within``: both methods gave a motion to compare and every
        measured difference is within its tolerance; ``nothing_to_compare``: the same verdict
        but nothing to compare (claim a: no orbit by either method; claim b: neither settles);
        ``outside_tolerance``: compared, a difference above its tolerance (whatever the
        verdicts); ``different_verdict``: the two methods give different verdicts on the claim.
    """
    out = {
        "checks": len(checks),
        "compared_within": 0,
        "nothing_to_compare": 0,
        "outside_tolerance": 0,
        "different_verdict": 0,
    }
    for c in checks:
        if c["exact"] != c["independent"]:
            out["different_verdict"] += 1
        if c["claim"] == "a":
            nothing = c["comparison"]["periodicity_residual"] is None
            within = bool(c["comparison"]["agree"])
        else:
            nothing = c["exact_period_multiple"] == 0 and c["independent_period_multiple"] == 0
            within = bool(c["details"].get("agree", False))
        if nothing:
            out["nothing_to_compare"] += c["exact"] == c["independent"]
        elif within:
            out["compared_within"] += 1
        else:
            out["outside_tolerance"] += 1
    return out
