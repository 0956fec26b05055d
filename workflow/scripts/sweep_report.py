"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the sweep stage's
numbers for the report, as LaTeX macros and a booktabs table (no number is typed by hand).

Outputs:

* ``results/report/sweeps.json`` -- the stage's record
  (:class:`impactdamper.reporting.latex.MacroFile`), from which the macros below and the
  README summary's numbers are rendered;
* ``paper/generated/sweep_macros.tex`` -- the sweep's extent and settling cap, the regime
  sequence of each direction (runs of at least ``MIN_RUN`` points), the three closed-form
  checks (each difference with the tolerance it is held to, and for the lift-off the offset
  the solver's grazing resolution predicts, see :func:`liftoff_resolution_offset`), the
  overlaps of the two sweep directions (hysteresis), and the bistable rows of each regime map
  (:func:`bistable_rows`);
* ``paper/generated/sweep_transitions.tex`` -- the main transitions (between runs of at least
  ``MIN_RUN`` points; changes inside the chaotic bands are in ``figures/sweep_transitions.csv``),
  each identified where possible: with a closed-form check (quoting the check's own numbers,
  the same macros as the text), with a special point of a continued orbit branch
  (``figures/orbit_special_points.csv``), or with the same change located by the other sweep
  direction; a change to or from np that none of these explains is marked as an edge of the
  settling budget;
* ``paper/generated/sweep_timing.tex`` -- the benchmarks (wall and processor times measured
  inside the jobs). The only output of the stage that changes from run to run.
"""

import math
from pathlib import Path

import numpy as np

from impactdamper.studies import gapsweep as gs
from impactdamper.reporting import latex
from impactdamper.reporting.latex import MacroFile, render_macros
from impactdamper.reporting.records import cell_float, read_csv, read_json, start_stage, write_json

# A run of one label shorter than this many sweep points is not a "main" regime (the chaotic
# bands flicker between np and narrow periodic windows).
MIN_RUN = 5
CHECK_NAMES = {"liftoff": "LiftOff", "first_contact": "FirstContact", "alg1_grazing": "AlgOneGrazing"}
CHECK_MATCH = {"liftoff": ("up", "stuck"), "first_contact": ("down", "0/1"), "alg1_grazing": ("down", "1/1")}
CHECK_TEXT = {"liftoff": "(a) lift-off", "first_contact": "(b) first contact", "alg1_grazing": "(c) Alg.~1 grazing"}
# A transition is identified with a special point of a continued branch, or with the same
# change located by the other sweep direction, when they are within this share of the sweep
# step (the step is the sweep's resolution; the bisections are 1000 times finer).
MATCH_STEPS = 0.05
SPECIAL_TEXT = {"period_doubling": "PD", "neimark_sacker": "NS", "fold": "fold", "grazing_interior": "grazing",
                "grazing_velocity": "grazing"}
# The inputs the rule passes since the transitions table names special points, overlaps and
# caps (figures/ paths, used when a rule that predates them runs the script).
DEFAULT_INPUTS = {"settings": "figures/sweep_gap_settings.json", "special": "figures/orbit_special_points.csv",
                  "maps": ["figures/map_theta.csv", "figures/map_damping.csv"],
                  "map_curves": ["figures/map_theta_curves.csv", "figures/map_damping_curves.csv"],
                  "map_settings": ["figures/map_theta_settings.json", "figures/map_damping_settings.json"]}
MAP_MACRO = {"theta": "Theta", "damping": "Damping"}
# What the stage's record holds (results/report/sweeps.json).
RECORD_WHAT = "the sweeps stage's numbers for the report (paper/generated/sweep_macros.tex) and the README"
# Cells of the bistable label a map row must hold beyond U1/x_st to count as on it.
BISTABLE_MIN_CELLS = 3
# Rows in a row all on the bistable label that end the alternating stretch.
BISTABLE_STEADY_ROWS = 5


def _tex_label(lab: str) -> str:
    return {"stuck": "S", "np": "np"}.get(lab, lab)


def _num(x, digits: int = 10) -> str:
    return "--" if x is None else f"{x:.{digits}g}"


def tex_sci(x, digits: int = 2) -> str:
    """x as LaTeX math: 6.6\\times10^{-6}; 10^{-9} for an exact power of ten; '--' for None."""
    return latex.tex_sci(x, digits, missing="\\text{--}", powers_of_ten=True)


def _macro(name: str, value) -> tuple:
    """A macro of the stage's record (:class:`impactdamper.reporting.latex.MacroFile`)."""
    return name, value


def main_runs(rows, direction: str):
    rs = [r for r in rows if r["direction"] == direction]
    runs = gs.runs([float(r["value"]) for r in rs], [r["label"] for r in rs])
    return [r for r in runs if r[3] >= MIN_RUN]


def sequence(runs, ascending: bool) -> str:
    seq = [_tex_label(r[0]) for r in (runs if ascending else runs[::-1])]
    out = [s for i, s in enumerate(seq) if i == 0 or s != seq[i - 1]]
    return " $\\to$ ".join(out)


# --- the lift-off check ------------------------------------------------------------------------
def liftoff_resolution_offset(base: dict, gap_tol: float) -> float:
    """How far past the analytic lift-off threshold the simulation keeps the bodies in contact.

    Past the threshold by eps = (Delta0 - Delta_lift)/x_st, the joined bodies' contact force
    F(t) = m2 w^2 |X| sin(...) - c2 Delta0 dips below zero by c2 eps x_st for a time 2 tau,
    tau^2 = 2 omega2^2 eps/(omega^4 |X|/x_st). Let go, the gap would open with the relative
    acceleration -F (1/m1 + 1/m2) = (1 + mu) omega2^2 eps x_st (1 - t^2/tau^2) and reach, when F
    is positive again, (4/3) (1 + mu) omega2^2 eps tau^2 x_st = C eps^2 x_st with

        C = (8/3) (1 + mu) (N/theta)^4 |1 - (1 + mu) theta^2 + 2 i delta1 theta|

    (leading order in eps). The event solver keeps contact through a dip whose gap stays at or
    below its grazing resolution gap_tol x_st (EventDrivenSolver._dip_unresolved), so the
    label stays "stuck" up to eps = sqrt(gap_tol/C). Returns that eps.
    """
    mu, n, theta, delta1 = (float(base[k]) for k in ("mu", "N", "theta", "delta1"))
    d = abs(1.0 - (1.0 + mu) * theta**2 + 2j * delta1 * theta)
    c = 8.0 / 3.0 * (1.0 + mu) * (n / theta) ** 4 * d
    return math.sqrt(gap_tol / c)


# --- identification of the table's transitions --------------------------------------------------
def special_match(t: dict, special: list[dict], tol: float):
    """The special point of a continued branch labelled like either side of transition t,
    nearest to it and within tol: (text, gap), or None."""
    value = float(t["value"])
    cands = [s for s in special if s["label"] in (t["before"], t["after"])
             and abs(cell_float(s["gap"]) - value) <= tol]
    if not cands:
        return None
    s = min(cands, key=lambda s: abs(cell_float(s["gap"]) - value))
    return f"{SPECIAL_TEXT.get(s['kind'], s['kind'])} of {s['label']}", cell_float(s["gap"])


def mirror_match(t: dict, trans: list[dict], tol: float):
    """The same change located by the other sweep direction (labels swapped) within tol."""
    value = float(t["value"])
    other = "down" if t["direction"] == "up" else "up"
    cands = [u for u in trans if u["direction"] == other and u["before"] == t["after"] and u["after"] == t["before"]
             and abs(float(u["value"]) - value) <= tol]
    if not cands:
        return None
    return min(cands, key=lambda u: abs(float(u["value"]) - value))


# --- overlaps of the two directions (hysteresis) ------------------------------------------------
def _run_intervals(rows, trans, direction: str):
    """Runs of the direction's labels, each (label, lo, hi, first, last): lo and hi are the
    bisected transitions at its ends (the midpoint to the neighbour where none was bisected)."""
    rs = sorted((r for r in rows if r["direction"] == direction), key=lambda r: float(r["value"]))
    values = [float(r["value"]) for r in rs]
    at = [float(t["value"]) for t in trans if t["direction"] == direction]
    out = []
    for lab, a, b, _ in gs.runs(values, [r["label"] for r in rs]):
        i, j = values.index(a), values.index(b)
        lo = values[0] if i == 0 else next((v for v in at if values[i - 1] < v <= a), 0.5 * (values[i - 1] + a))
        hi = values[-1] if j == len(values) - 1 else next((v for v in at if b <= v < values[j + 1]),
                                                          0.5 * (b + values[j + 1]))
        out.append((lab, lo, hi, a, b))
    return out


def overlaps(rows, trans) -> list[dict]:
    """Where the two directions settle on different periodic motions (np and err left out):
    list of {"down": labels, "up": labels, "lo", "hi"}, adjacent pieces sharing a label merged."""
    loose = ("np", "err")
    up, down = _run_intervals(rows, trans, "up"), _run_intervals(rows, trans, "down")
    pieces = []
    for lu, ulo, uhi, ua, ub in up:
        for ld, dlo, dhi, da, db in down:
            if lu == ld or lu in loose or ld in loose or max(ua, da) > min(ub, db):
                continue  # the same motion, or no sweep point shared
            pieces.append({"up": [lu], "down": [ld], "lo": max(ulo, dlo), "hi": min(uhi, dhi)})
    pieces.sort(key=lambda p: p["lo"])
    merged = []
    for p in pieces:
        q = merged[-1] if merged else None
        if q and abs(q["hi"] - p["lo"]) < 1e-12 and (q["up"][-1] == p["up"][0] or q["down"][-1] == p["down"][0]):
            for side in ("up", "down"):
                q[side] += [lab for lab in p[side] if lab not in q[side]]
            q["hi"] = p["hi"]
        else:
            merged.append(p)
    return merged


def _and(items: list[str]) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def overlap_text(ovs: list[dict]) -> str:
    parts = [f"{_and(o['down'])} (downward) with {_and(o['up'])} (upward) on $({o['lo']:.3f}, {o['hi']:.3f})$"
             for o in ovs]
    return "none" if not parts else (parts[0] if len(parts) == 1 else "; ".join(parts[:-1]) + "; and " + parts[-1])


def np_only_labels(rows) -> list[str]:
    """Periodic labels met in one direction at sweep points where the other did not settle
    (np), on runs of at least two points, in order of the gap."""
    up = {float(r["value"]): r["label"] for r in rows if r["direction"] == "up"}
    down = {float(r["value"]): r["label"] for r in rows if r["direction"] == "down"}
    values = sorted(set(up) & set(down))
    out = []
    for key, _a, _b, n in gs.runs(values, [f"{up[v]}|{down[v]}" for v in values]):
        u, d = key.split("|")
        if n >= 2 and (u == "np") != (d == "np"):
            lab = d if u == "np" else u
            if lab not in ("err",) and lab not in out:
                out.append(lab)
    return out


# --- the regime maps' bistable rows ---------------------------------------------------------------
def read_map(path):
    lines = [ln.split(",") for ln in Path(path).read_text().splitlines()]
    gaps = np.array([float(x) for x in lines[0][1:]])
    slow = np.array([float(ln[0]) for ln in lines[1:]])
    return slow, gaps, np.array([ln[1:] for ln in lines[1:]])


def bistable_rows(map_csv, curves_csv) -> dict | None:
    """Rows of a map that alternate between the no-contact motion 0/1 and an impacting motion
    where both exist (gap above U1/x_st, where 0/1 always exists).

    The impacting label is the one (other than 0/1, np, err) with most cells beyond U1. A row is
    on it with at least BISTABLE_MIN_CELLS such cells. The alternating stretch runs from the
    first row on it to the last row off it before BISTABLE_STEADY_ROWS rows in a row are on it.
    Returns {"label", "lo", "hi", "on", "off"} (slow-parameter values, row counts) or None.
    """
    slow, gaps, labels = read_map(map_csv)
    u1 = np.array([float(r["first_contact"]) for r in read_csv(curves_csv)])
    beyond = gaps[None, :] > u1[:, None]
    counts: dict[str, int] = {}
    for lab in labels[beyond]:
        if lab not in ("0/1", "np", "err"):
            counts[lab] = counts.get(lab, 0) + 1
    if not counts:
        return None
    lab = max(sorted(counts), key=counts.get)
    on = [int(np.sum((labels[i] == lab) & beyond[i])) >= BISTABLE_MIN_CELLS for i in range(len(slow))]
    if True not in on:
        return None
    first = on.index(True)
    last_off = None
    steady = 0
    for i in range(first, len(slow)):
        steady = steady + 1 if on[i] else 0
        if not on[i]:
            last_off = i
        if steady >= BISTABLE_STEADY_ROWS and last_off is not None:
            break
    if last_off is None:
        return None
    stretch = on[first:last_off + 1]
    return {"label": lab, "lo": float(slow[first]), "hi": float(slow[last_off]), "on": sum(stretch),
            "off": len(stretch) - sum(stretch)}


# --- outputs -----------------------------------------------------------------------------------
def macros(rows, trans, checks_doc, settings, maps: dict) -> MacroFile:
    checks = {c["name"]: c for c in checks_doc["checks"]}
    values = sorted({float(r["value"]) for r in rows})
    sweep, solver = settings["sweep"], settings["solver"]
    m = [
        "% Generated by workflow/scripts/sweep_report.py: do not edit.",
        "% Numbers are bare (for math mode) unless they are text (sequences, lists).",
        _macro("SweepPoints", len(values)),
        _macro("SweepGapMin", f"{values[0]:g}"),
        _macro("SweepGapMax", f"{values[-1]:g}"),
        _macro("SweepGapStep", f"{(values[-1] - values[0]) / (len(values) - 1):.4g}"),
        _macro("SweepMinRun", MIN_RUN),
        _macro("SweepMaxPeriods", int(sweep["max_periods"])),
        _macro("SweepMaxPeriodsAfterNonperiodic", int(sweep["max_periods_after_nonperiodic"])),
        _macro("SweepMaxPeriodMultiple", int(sweep["max_period_multiple"])),
        _macro("SweepSequenceUp", sequence(main_runs(rows, "up"), True)),
        _macro("SweepSequenceDown", sequence(main_runs(rows, "down"), False)),
        _macro("SweepTransitionsBisected", len(trans)),
        _macro("SweepTransitionTol", tex_sci(float(checks_doc["transition_xtol"]))),
        _macro("SweepCheckTolerance", tex_sci(float(checks_doc["check_xtol"]))),
        _macro("SweepGapTol", tex_sci(float(solver["gap_tol"]))),
    ]
    for name, macro in CHECK_NAMES.items():
        c = checks.get(name, {})
        diff = c.get("analytic_minus_located")
        m += [
            _macro(f"Sweep{macro}Analytic", _num(c.get("analytic"), 10)),
            _macro(f"Sweep{macro}Numeric", _num(c.get("numeric"), 10)),
            _macro(f"Sweep{macro}Located", _num(c.get("located"), 10)),
            # |analytic - located| of figures/sweep_checks.json, the check's own bisection.
            _macro(f"Sweep{macro}Difference", "\\text{--}" if diff is None else tex_sci(abs(diff))),
            _macro(f"Sweep{macro}DifferencePrecise", "\\text{--}" if diff is None else tex_sci(abs(diff), 3)),
            _macro(f"Sweep{macro}NumericDifference", "\\text{--}" if c.get("analytic_minus_numeric") is None
                   else tex_sci(abs(c["analytic_minus_numeric"]))),
        ]
    if checks.get("alg1_grazing", {}).get("continuation") is not None:
        m.append(_macro("SweepAlgOneGrazingContinuation", f"{checks['alg1_grazing']['continuation']:.10g}"))
    eps = liftoff_resolution_offset(checks_doc["base"], float(solver["gap_tol"]))
    m.append(_macro("SweepLiftOffResolutionOffset", tex_sci(eps, 3)))
    ovs = overlaps(rows, trans)
    m += [_macro("SweepOverlapCount", len(ovs)), _macro("SweepOverlaps", overlap_text(ovs)),
          _macro("SweepNpOnlyLabels", _and(np_only_labels(rows)) if np_only_labels(rows) else "none"),
          _macro("SweepMatchSteps", f"{1 / MATCH_STEPS:g}")]
    for name, (map_csv, curves_csv, map_settings) in maps.items():
        M = MAP_MACRO[name]
        ms = read_json(map_settings)["maps"]
        b = bistable_rows(map_csv, curves_csv)
        m += [_macro(f"Map{M}MaxPeriods", int(ms["max_periods"])),
              _macro(f"Map{M}MaxPeriodsAfterNonperiodic", int(ms["max_periods_after_nonperiodic"])),
              _macro(f"Map{M}BistableLabel", b["label"] if b else "--"),
              _macro(f"Map{M}BistableLow", f"{b['lo']:.3f}" if b else "--"),
              _macro(f"Map{M}BistableHigh", f"{b['hi']:.3f}" if b else "--"),
              _macro(f"Map{M}BistableRowsOn", b["on"] if b else 0),
              _macro(f"Map{M}BistableRowsOff", b["off"] if b else 0)]
    return MacroFile(m)


def table(rows, trans, checks_doc, special) -> str:
    """The main transitions: where a run of >= MIN_RUN points ends and the next main run begins."""
    checks = {c["name"]: c for c in checks_doc["checks"]}
    values = sorted({float(r["value"]) for r in rows})
    tol = MATCH_STEPS * (values[-1] - values[0]) / (len(values) - 1)
    lines = ["% Generated by workflow/scripts/sweep_report.py: do not edit.",
             "\\begin{tabular}{llrlrl}", "\\toprule",
             "sweep & transition & $\\Delta_0/x_{st}$ & identified as & at & $|$difference$|$ \\\\", "\\midrule"]
    marks = set()
    for direction in ("up", "down"):
        runs = main_runs(rows, direction)
        ordered = runs if direction == "up" else runs[::-1]
        for a, b in zip(ordered[:-1], ordered[1:]):
            if a[0] == b[0]:
                continue
            lo, hi = sorted((a[2], b[1]) if direction == "up" else (a[1], b[2]))
            cands = [t for t in trans if t["direction"] == direction and lo <= float(t["value"]) <= hi
                     and t["before"] == a[0]]
            if not cands:
                continue
            t = cands[0] if direction == "up" else cands[-1]
            value = f"${float(t['value']):.6f}$"
            ident, at, diff = "", "", ""
            check = next((name for name, (d, before) in CHECK_MATCH.items()
                          if d == direction and before == a[0] and checks.get(name, {}).get("analytic") is not None
                          and checks[name].get("located") is not None
                          and abs(checks[name]["analytic"] - float(t["value"])) < 0.5), None)
            if check is not None:
                # The closed-form check's own numbers (the text's macros): its relocation to
                # check_xtol by simulation, the analytic value, and the difference against the tolerance.
                M = CHECK_NAMES[check]
                value = f"$\\Sweep{M}Located$"
                ident, at = CHECK_TEXT[check], f"$\\Sweep{M}Analytic$"
                diff = f"$\\Sweep{M}Difference$ (tol.\\ $\\SweepCheckTolerance$)"
                marks.add("check")
            elif (sp := special_match(t, special, tol)) is not None:
                ident, at, diff = sp[0] + "$^{o}$", f"${sp[1]:.6f}$", f"${tex_sci(abs(sp[1] - float(t['value'])))}$"
                marks.add("orbit")
            elif "np" in (t["before"], t["after"]) and (u := mirror_match(t, trans, tol)) is not None:
                ident, at = "both sweeps$^{s}$", f"${float(u['value']):.6f}$"
                diff = f"${tex_sci(abs(float(u['value']) - float(t['value'])))}$"
                marks.add("mirror")
            elif "np" in (t["before"], t["after"]):
                ident = "budget edge$^\\ddagger$"
                marks.add("budget")
            text = f"{_tex_label(t['before'])} $\\to$ {_tex_label(t['after'])}"
            if t["after"] != b[0]:
                text += f" ($\\to\\dots\\to$ {_tex_label(b[0])})"
            if t["one_sided"] == "1":
                value += "$^\\dagger$"
                marks.add("one_sided")
            lines.append(f"{'upward' if direction == 'up' else 'downward'} & {text} & {value} & {ident} & {at} & "
                         f"{diff} \\\\")
    lines += ["\\bottomrule", "\\end{tabular}"]
    notes = []
    if "check" in marks:
        notes.append("(a)--(c): the closed-form checks of the text, with their own numbers: "
                     "$\\Delta_0/x_{st}$ relocated by simulation alone to $\\SweepCheckTolerance$, the analytic "
                     "value, and $|$analytic$-$located$|$ beside the tolerance it is held to. Other rows: "
                     "$\\Delta_0/x_{st}$ bisected to $\\SweepTransitionTol$.")
    if "orbit" in marks:
        notes.append("$^{o}$\\,A special point of the branch continued in Section~\\ref{sec:orbits} "
                     "(Table~\\ref{tab:special}), within 1/\\SweepMatchSteps{} of the sweep step: the motion "
                     "on that side ends or loses stability there.")
    if "mirror" in marks:
        notes.append("$^{s}$\\,The other sweep direction locates the same change (labels swapped) within "
                     "1/\\SweepMatchSteps{} of the sweep step: the periodic motion's own end, met from both sides.")
    if "budget" in marks:
        notes.append("$^\\ddagger$\\,Edge of the settling budget, not a transition: np (no period "
                     "$k\\le\\SweepMaxPeriodMultiple$ settled within the cap of \\SweepMaxPeriods{} periods, "
                     "\\SweepMaxPeriodsAfterNonperiodic{} after a nonperiodic neighbour) on "
                     "one side, and no closed form, special point or other direction puts a change there. "
                     "The value is where the motion started from the neighbour stops, or starts, settling "
                     "within the cap; a longer cap can move it.")
    if "one_sided" in marks:
        notes.append("$^\\dagger$\\,One-sided: the new motion was met at a single point (a sweep point or the "
                     "first midpoint); every later midpoint, started from the first motion, kept it. Entering "
                     "a window from a nonperiodic band depends on the start.")
    if notes:
        lines += ["", "\\smallskip", "\\parbox{\\linewidth}{\\footnotesize " + " ".join(notes) + "}"]
    return "\n".join(lines) + "\n"


def timing(sweep_timing, map_timings) -> str:
    sw = read_json(sweep_timing)
    t = ["% Generated by workflow/scripts/sweep_report.py: benchmark, changes from run to run.",
         f"\\newcommand{{\\SweepBenchPoints}}{{{sw['points']}}}",
         f"\\newcommand{{\\SweepBenchProcesses}}{{{sw['processes']} process{'' if sw['processes'] == 1 else 'es'}}}",
         f"\\newcommand{{\\SweepBenchWall}}{{{sw['wall_s']:.1f}}}",
         f"\\newcommand{{\\SweepBenchCpuUp}}{{{sw['cpu_s']['up']:.1f}}}",
         f"\\newcommand{{\\SweepBenchCpuDown}}{{{sw['cpu_s']['down']:.1f}}}",
         f"\\newcommand{{\\SweepBenchLoad}}{{{sw['machine_before']['load_average'][0]:.1f}}}",
         f"\\newcommand{{\\SweepBenchTarget}}{{{sw['target_wall_s']:.0f}}}"]
    for path in map_timings:
        mt = read_json(path)
        name = MAP_MACRO[mt["map"]]
        t += [f"\\newcommand{{\\Map{name}Cells}}{{{mt['shape'][0]} $\\times$ {mt['shape'][1]}}}",
              f"\\newcommand{{\\Map{name}Chunks}}{{{mt['chunks']}}}",
              f"\\newcommand{{\\Map{name}Wall}}{{{mt['wall_s']:.0f}}}",
              f"\\newcommand{{\\Map{name}Cpu}}{{{mt['cpu_s']:.0f}}}",
              f"\\newcommand{{\\Map{name}Target}}{{{mt['target_wall_s']:.0f}}}"]
    return "\n".join(t) + "\n"


def report(sweep_csv, transitions_csv, checks_json, settings_json, special_csv, maps: dict, out_record, out_macros,
           out_table) -> None:
    """The deterministic outputs (the stage's record, JSON; from it the macros; the table), from
    the committed figures/ files. ``maps``: map name -> (map CSV, curves CSV, settings JSON)."""
    rows = read_csv(sweep_csv)
    trans = read_csv(transitions_csv)
    checks_doc = read_json(checks_json)
    settings = read_json(settings_json)
    special = read_csv(special_csv)
    write_json(out_record, macros(rows, trans, checks_doc, settings, maps).record(RECORD_WHAT), sort_keys=False)
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(render_macros(read_json(out_record)))
    Path(out_table).write_text(table(rows, trans, checks_doc, special))


def main(sweep_csv, transitions_csv, checks_json, sweep_timing, map_timings, out_record, out_macros, out_table,
         out_timing, *,
         settings_json=DEFAULT_INPUTS["settings"], special_csv=DEFAULT_INPUTS["special"], map_csvs=None,
         map_curves=None, map_settings=None) -> None:
    map_csvs = map_csvs or DEFAULT_INPUTS["maps"]
    map_curves = map_curves or DEFAULT_INPUTS["map_curves"]
    map_settings = map_settings or DEFAULT_INPUTS["map_settings"]
    maps = {read_json(s)["map"]: (c, k, s) for c, k, s in zip(map_csvs, map_curves, map_settings)}
    report(sweep_csv, transitions_csv, checks_json, settings_json, special_csv, maps, out_record, out_macros,
           out_table)
    Path(out_timing).write_text(timing(sweep_timing, map_timings))


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    start_stage(sm)
    # Inputs named in the rule; DEFAULT_INPUTS for a rule that predates them.
    got = {k: getattr(sm.input, k, None) or DEFAULT_INPUTS[k] for k in DEFAULT_INPUTS}
    main(sm.input.sweep, sm.input.transitions, sm.input.checks, sm.input.sweep_timing, list(sm.input.map_timings),
         sm.output.record, sm.output.macros, sm.output.table, sm.output.timing, settings_json=str(got["settings"]),
         special_csv=str(got["special"]), map_csvs=list(got["maps"]), map_curves=list(got["map_curves"]),
         map_settings=list(got["map_settings"]))
