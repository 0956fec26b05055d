"""Other readings of the paper's definitions at the stated Delta0/x_st (Timofeev,
Lyuminarskiy & Lyuminarskiy 2019, DOI 10.18698/0236-3941-2019-1-90-100): does any plausible
reading reproduce Fig. 2's behaviour, (a) a negative gap in Algorithm No. 1's orbit and (b)
T_c = 2T with three impacts from Algorithm No. 2, where the stated parameters give neither?
``workflow/scripts/other_readings.py`` runs :func:`evaluate_readings` and writes the records.

Every reading changes one thing and is evaluated with both algorithms; Algorithm No. 2's
settled motion is re-derived with the independent ``solve_ivp`` integrator. The readings:

* ``stated``: the parameters as stated (the baseline);
* ``printed_velocities``: step 1's example velocities exactly as printed, x1b' = 1/m1,
  x2b' = 1/m2 (same direction, so they close the gap and an impact comes first);
* ``random_states``: ``random_states`` random initial states (seeded), for coexisting motions;
* ``delta2_per_omega2``: delta2 = k2/(2 m2 omega2) = 0.05 (the suppressor's own frequency);
* ``delta_without_half``: delta_i = k_i/(m_i omega1) = 0.05 (no factor 2);
* ``gap_sign_flipped``: Delta0/x_st = +5.8;
* ``gap_per_relative_amplitude``: Delta0 = -5.8 |x2p - x1p| (the forced relative amplitude
  U1 of eqs. 12, 16 as the unit);
* ``gap_per_object_amplitude``: Delta0 = -5.8 |x1p| (the object's forced amplitude);
* ``x_st_with_c2``: x_st = P0/(c1 + c2) instead of P0/c1;
* ``mu_of_total``: mu = m2/(m1 + m2) = 0.08;
* ``R_as_loss``: R read as 1 - 0.7 = 0.3 (a loss coefficient, the other common convention;
  it contradicts the paper's own D = m_red (R + 1) of eq. 14);
* ``eq13_as_printed``: Algorithm No. 1 with eq. (13)'s second line as printed,
  x21s' = x1s' - x2s' (the opposite of eq. 12's x21s = x2s - x1s); Algorithm No. 2 does not
  use eq. (13).

Also scans R at the stated gap (grid ``R_step``, ends bisected to ``R_BISECT_TOL``) for where
each claim holds.
"""

from __future__ import annotations

import math
import types
from collections import Counter

import numpy as np

from impactdamper.studies.replication import cases as rep
from impactdamper.studies.replication import crosscheck as xc
from impactdamper.studies.config import parameters
from impactdamper.core.algorithm1 import unit_pulse_response
from impactdamper.core.events import Segment
from impactdamper.core.impact_law import impact_pulse
from impactdamper.core.linear import forced_amplitudes
from impactdamper.core.model import Model

__all__ = [
    "R_BISECT_TOL",
    "RANDOM_X",
    "RANDOM_GAP",
    "RANDOM_V",
    "readings",
    "evaluate",
    "random_states",
    "evaluate_readings",
]

R_BISECT_TOL = 1e-4
# The parameters the readings change, a column each in every row of the readings' table.
_READING_COLUMNS = ("gap", "R", "delta1", "delta2", "mu")
# Random initial states: object position within +-RANDOM_X x_st, gap in [0, RANDOM_GAP] x_st,
# velocities within +-RANDOM_V x_st omega1, start time anywhere in one period (the stated
# case's settled motion reaches |x1| ~ 5.6 x_st and closing velocities ~ 14 x_st omega1).
RANDOM_X, RANDOM_GAP, RANDOM_V = 10.0, 10.0, 15.0


def _alg1_eq13_as_printed(p):
    """Algorithm No. 1 with eq. (13)'s x21s' = x1s' - x2s' (as printed): eqs. (15)-(17) with
    that sign. Returns an object like Algorithm1Result's (exists, S, t_impact, state_after,
    negative_gap_intervals, min_gap, p) and the impact-law ratio S / (D v) of the orbit's
    own closing velocity v (1 for a consistent orbit)."""
    model = Model(p)
    z0 = unit_pulse_response(p, model)
    zT = model.free.free(p.T, z0)
    x21s_T, dx21s_T = zT[1] - zT[0], -(zT[3] - zT[2])  # the printed sign
    x1p, x2p = forced_amplitudes(p)
    U1 = abs(x2p - x1p)
    eps21 = math.atan2((x2p - x1p).imag, (x2p - x1p).real)
    D = impact_pulse(p, 1.0)  # eq. (14)'s D = m_red (1 + R)
    denom = 1.0 - D * dx21s_T
    U2 = D * x21s_T / denom * U1 * p.omega
    rho = p.Delta0 / math.hypot(U1, U2)
    out = types.SimpleNamespace(p=p, exists=False, negative_gap_intervals=(), min_gap=math.nan, ratio=math.nan)
    if abs(rho) > 1.0:
        return out
    zeta = math.atan2(U2, U1)
    for phi in (math.asin(rho) - zeta, math.pi - math.asin(rho) - zeta):
        S = D * U1 * p.omega * math.cos(phi) / denom
        if S > 0.0:
            break
    else:
        return out
    t_imp = ((phi - eps21) % (2.0 * math.pi)) / p.omega
    after = model.free.forced(t_imp) + S * z0
    seg = Segment(model.free, t_imp, after)
    scan = xc.gap_sign_scan(lambda s: float(model.gap_of(seg.state(t_imp + s * p.T))), xc.IVP_GAP_SAMPLES)
    before = seg.state(t_imp + p.T)
    out.exists, out.S, out.t_impact, out.state_after = True, S, t_imp, after
    out.negative_gap_intervals = scan.negative_intervals
    out.min_gap = float(scan.samples.min() / p.x_st)
    out.ratio = float(S / (D * (before[3] - before[2])))
    return out


def readings(base: dict) -> list[dict]:
    """The readings: id, description, parameter changes, initial state, Algorithm No. 1 variant."""
    p = parameters(base)
    x1p, x2p = forced_amplitudes(p)
    g = base["gap"]
    return [
        {"id": "stated", "reading": "the parameters as stated", "changes": {}},
        {
            "id": "printed_velocities",
            "reading": "step 1's velocities as printed, x1b' = 1/m1, x2b' = 1/m2 (same direction)",
            "changes": {},
            "state": [0.0, p.Delta0, 1.0 / p.m1, 1.0 / p.m2],
        },
        {
            "id": "delta2_per_omega2",
            "reading": "delta2 = k2/(2 m2 omega2)",
            "changes": {"delta2": base["delta2"] * base["N"]},
        },
        {
            "id": "delta_without_half",
            "reading": "delta_i = k_i/(m_i omega1) (no factor 2)",
            "changes": {"delta1": base["delta1"] / 2.0, "delta2": base["delta2"] / 2.0},
        },
        {"id": "gap_sign_flipped", "reading": "Delta0/x_st with the sign flipped", "changes": {"gap": -g}},
        {
            "id": "gap_per_relative_amplitude",
            "reading": "Delta0 in units of |x2p - x1p| (eq. 16's U1)",
            "changes": {"gap": g * abs(x2p - x1p) / p.x_st},
        },
        {
            "id": "gap_per_object_amplitude",
            "reading": "Delta0 in units of |x1p| (the object's forced amplitude)",
            "changes": {"gap": g * abs(x1p) / p.x_st},
        },
        {
            "id": "x_st_with_c2",
            "reading": "x_st = P0/(c1 + c2)",
            "changes": {"gap": g / (1.0 + base["mu"] * base["N"] ** 2)},
        },
        {"id": "mu_of_total", "reading": "mu = m2/(m1 + m2)", "changes": {"mu": base["mu"] / (1.0 - base["mu"])}},
        {
            "id": "R_as_loss",
            "reading": "R read as 1 - R (contradicts eq. 14's D = m_red (R + 1))",
            "changes": {"R": 1.0 - base["R"]},
        },
        {
            "id": "eq13_as_printed",
            "reading": "eq. (13) as printed, x21s' = x1s' - x2s' (Algorithm No. 1 only)",
            "changes": {},
            "eq13_printed": True,
        },
    ]


def evaluate(base: dict, solver: dict, verdict: dict, r: dict) -> tuple[dict, dict]:
    p = parameters(dict(base, **r["changes"]))
    if r.get("eq13_printed"):
        a = _alg1_eq13_as_printed(p)
    else:
        a = rep.run_alg1(p, solver)
    state = np.array(r["state"]) if "state" in r else None
    s = rep.run_steady(p, solver, state=state)
    ivp_a = xc.alg1_ivp(a, **xc.ivp_options(verdict)) if a.exists else {"claim_a": False}
    ivp_b = xc.alg2_crosscheck(p, s, verdict, solver, state=state)
    iv = a.negative_gap_intervals[0] if a.negative_gap_intervals else (None, None)
    row = {
        "id": r["id"],
        "reading": r["reading"],
        **{k: getattr(p, k) for k in _READING_COLUMNS},
        "alg1_exists": a.exists,
        "alg1_t1": iv[0],
        "alg1_t2": iv[1],
        "alg1_min_gap": a.min_gap if a.exists else None,
        "claim_a": rep.claim_a(a),
        "alg2_regime": s.regime,
        "alg2_period_multiple": s.period_multiple,
        "alg2_impacts_per_cycle": s.impacts_per_cycle,
        "claim_b": rep.claim_b(s),
        "ivp_claim_a": ivp_a["claim_a"],
        "ivp_claim_b": ivp_b["claim_b"],
        "ivp_cycle_time_diff": ivp_b["max_time_difference_over_T"],
        "ivp_cycle_velocity_diff": ivp_b["max_velocity_difference_rel"],
        "ivp_cycle_agree": ivp_b["agree"],
    }
    row["reproduces"] = row["claim_a"] and row["claim_b"]
    details = {"alg1_ivp": ivp_a, "alg2_ivp": ivp_b}
    if r.get("eq13_printed") and a.exists:
        details["impact_law_ratio"] = a.ratio  # S/(D v): 1 for an orbit that obeys eq. (14)
    return row, details


def random_states(base: dict, solver: dict, verdict: dict) -> dict:
    """Settled motions from seeded random initial states at the stated parameters."""
    p = parameters(base)
    rng = np.random.default_rng(int(verdict["seed"]))
    motions, agree, worst_time = Counter(), 0, 0.0
    n = int(verdict["random_states"])
    for _ in range(n):
        x1 = rng.uniform(-RANDOM_X, RANDOM_X) * p.x_st
        gap = rng.uniform(0.0, RANDOM_GAP) * p.x_st
        v1, v2 = rng.uniform(-RANDOM_V, RANDOM_V, 2) * p.x_st * p.omega1
        t0 = float(rng.uniform(0.0, p.T))
        state = np.array([x1, x1 + p.Delta0 - gap, v1, v2])
        s = rep.run_steady(p, solver, t0=t0, state=state)
        ivp = xc.alg2_crosscheck(p, s, verdict, solver, state=state, t0=t0)
        # Agreement is measured: the aligned cycles within tolerance (both settled), or both
        # unsettled within the cap.
        both_unsettled = ivp["period_multiple"] == 0 and s.period_multiple == 0
        agree += int(ivp["claim_b"] == rep.claim_b(s) and (ivp["agree"] or both_unsettled))
        worst_time = max(worst_time, ivp["max_time_difference_over_T"] if not both_unsettled else 0.0)
        phase = round(s.impacts[0].phase, 6) if s.impacts else None
        motions[(s.regime, s.period_multiple, s.impacts_per_cycle, phase)] += 1
    found = [
        {"regime": k[0], "period_multiple": k[1], "impacts_per_cycle": k[2], "first_impact_phase": k[3], "count": c}
        for k, c in sorted(motions.items(), key=lambda kv: (-kv[1], str(kv[0])))
    ]
    return {
        "count": n,
        "seed": int(verdict["seed"]),
        "motions": found,
        "ivp_agree": agree,
        "ivp_max_time_difference_over_T": worst_time,
        "ivp_time_tol": float(verdict["crosscheck_time_tol"]),
        "claim_b_found": any(
            m["regime"] == "multi_impact"
            and m["period_multiple"] == rep.CLAIM_B_PERIOD_MULTIPLE
            and m["impacts_per_cycle"] == rep.CLAIM_B_IMPACTS
            for m in found
        ),
        "box": {"x1": RANDOM_X, "gap": RANDOM_GAP, "velocity_per_omega1": RANDOM_V},
    }


def _r_ranges(base: dict, solver: dict, verdict: dict) -> dict:
    """Where each claim holds as R varies over [0, 1] at the stated gap (ends bisected)."""
    Rs = rep.grid(0.0, 1.0, float(verdict["R_step"]))

    def pa(R):
        return rep.claim_a(rep.run_alg1(parameters(dict(base, R=float(R))), solver))

    def pb(R):  # compiled: the grid and its bisections are many settled runs
        return rep.claim_b(rep.run_steady(parameters(dict(base, R=float(R))), solver))

    out = {"R_step": float(verdict["R_step"]), "bisect_tol": R_BISECT_TOL}
    for name, pred in (("claim_a", pa), ("claim_b", pb)):
        out[name] = rep.ranges(Rs, [pred(R) for R in Rs], pred, R_BISECT_TOL)
    out["both"] = rep.overlap(out["claim_a"], out["claim_b"])
    return out


def evaluate_readings(reference: dict, solver: dict, verdict: dict) -> tuple[list[dict], dict]:
    """Evaluate every reading (the module docstring's list) at the stated gap, the random
    initial states and the R scan.

    Returns
    -------
    rows : list of dict
        One row per reading (its claims by both algorithms and the ``solve_ivp`` check).
    result : dict
        The rows, each reading's details, the random states' motions and the R ranges.
    """
    base = parameters(reference).to_dict()
    rows, details = [], {}
    for r in readings(base):
        row, d = evaluate(base, solver, verdict, r)
        rows.append(row)
        details[r["id"]] = d
    rnd = random_states(base, solver, verdict)
    rows.append(
        {
            "id": "random_states",
            "reading": f"{rnd['count']} random initial states (seed {rnd['seed']})",
            **{k: base[k] for k in _READING_COLUMNS},
            "alg2_regime": "; ".join(f"{m['count']}x {m['regime']} k={m['period_multiple']}" for m in rnd["motions"]),
            "claim_a": rows[0]["claim_a"],
            "claim_b": rnd["claim_b_found"],
            "reproduces": rows[0]["claim_a"] and rnd["claim_b_found"],
        }
    )
    result = {
        "paper": rep.PAPER,
        "stated_gap": base["gap"],
        "readings": rows,
        "details": details,
        "random_states": rnd,
        "R_ranges": _r_ranges(base, solver, verdict),
    }
    return rows, result
