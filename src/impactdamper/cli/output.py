"""The command line's answers written out: each command's result as text (one printer per
command) or as one JSON object, and a write that fails (a closed pipe, a full disk) as one line
on stderr and status 1 instead of a traceback."""

from __future__ import annotations

import contextlib
import io
import json
import os
import sys
from collections.abc import Callable

from impactdamper.cli.parser import PROG
from impactdamper.reporting.records import clean

__all__ = ["PRINTERS", "write_answer", "output_failed"]


def write_answer(result: dict, printer: Callable[[dict], None], as_json: bool) -> int:
    """Write ``result`` to stdout, as one JSON object (``as_json``) or as ``printer`` shows it,
    all at once; returns the exit status (1, with one line on stderr, if it cannot be written)."""
    if as_json:
        text = json.dumps(clean(result)) + "\n"
    else:
        buffer = io.StringIO()
        with contextlib.redirect_stdout(buffer):
            printer(result)
        text = buffer.getvalue()
    if sys.stdout is None:  # started with stdout closed (``>&-``): nowhere to write
        return output_failed(OSError(9, "standard output is closed"))
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except OSError as err:
        return output_failed(err)
    return 0


class _Discard(io.TextIOBase):
    """Where output goes once it cannot be written: nowhere, without further errors."""

    def write(self, text: str) -> int:
        return len(text)


def output_failed(err: OSError) -> int:
    """Status 1 and one line on stderr for output that cannot be written; stdout is pointed at
    nowhere, so that nothing later fails on it again."""
    # Point the stdout file descriptor at /dev/null, so that the interpreter's own flush at exit
    # does not fail again (it would print "Exception ignored ... BrokenPipeError"), and stop
    # writing to it here.
    with contextlib.suppress(OSError, ValueError, AttributeError, io.UnsupportedOperation):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    sys.stdout = _Discard()
    with contextlib.suppress(OSError, ValueError):
        print(f"{PROG}: error: cannot write the output: {err.strerror or err}", file=sys.stderr)
    return 1


def _print_alg1(r: dict) -> None:
    if not r["exists"]:
        print(f"Algorithm No. 1: no orbit ({r['reason']})")
        return
    print(
        f"Algorithm No. 1: impact phase {r['impact_phase']:.12f} T, S = {r['S']:.10g} N s, "
        f"closing velocity {r['velocity']:.10g} m/s"
    )
    if r["negative_gap_intervals"]:
        ivs = ", ".join(f"({a:.6f}, {b:.6f})" for a, b in r["negative_gap_intervals"])
        print(f"  gap negative on {ivs} T after the impact (min {r['min_gap']:.6g} x_st): the orbit is not admissible")
    else:
        print(f"  gap never negative (smallest interior minimum {r['min_gap']:.6g} x_st): admissible")


def _print_steady(r: dict) -> None:
    print(
        f"regime {r['regime']}, T_c = {r['period_multiple']} T, {r['impacts_per_cycle']} impacts per cycle, "
        f"contact {100 * r['contact_fraction']:.2f} % of the cycle, max |x1|/x_st = {r['x1_max']:.6f} "
        f"({r['periods_simulated']} periods simulated)"
    )
    for i, imp in enumerate(r["impacts"], 1):
        print(
            f"  t{i} = {imp['t_over_T']:.9f} T (phase {imp['phase']:.9f}), v = {imp['velocity']:.9g} m/s, "
            f"S = {imp['impulse']:.9g} N s"
        )


def _print_orbit(r: dict) -> None:
    _print_steady(r)
    if not r["solved"]:
        print(f"  not solved directly: {r['reason']}")
        return
    print(
        f"  solved directly (seed {r['seed']}, {r['newton_iterations']} Newton iterations, residual "
        f"{r['residual']:.2g}); admissible: {'yes' if r['admissible'] else 'no, ' + r['reason']}; "
        f"stable: {'yes' if r['stable'] else 'no'}"
    )
    print("  Floquet multipliers |mu|: " + ", ".join(f"{m:.9f}" for m in r["multipliers"]))


def _print_response(r: dict) -> None:
    print(
        f"peak max|x1|/x_st over the band {r['peak_max_abs_x1']:.6f} at theta {r['peak_theta']:.6f} "
        f"({r['peak_branch']}; the grid's largest sample {r['grid_peak_max_abs_x1']:.6f}), band average "
        f"{r['band_average_max_abs_x1']:.6f}, largest pulse {r['peak_impulse']:.6g} m1 x_st omega, at most "
        f"{r['impacts_per_period']:g} impacts per period, {r['hysteresis_points']} theta values with hysteresis"
        + (
            f"; {r['failed_points']} of {len(r['points'])} theta values failed (err): the peak and the loads are over "
            "the others only"
            if r["failed_points"]
            else ""
        )
    )
    print("   theta   up     down   max|x1| up/down       max|x2| up   impacts/T  peak pulse  linear |x1|")
    for q in r["points"]:
        u, d = q["up"], q["down"]
        print(
            f"  {q['theta']:.4f}  {u['label']:<6} {d['label']:<6} {u['max_abs_x1']:9.5f} {d['max_abs_x1']:9.5f}  "
            f"{u['max_abs_x2']:9.5f}  {u['impacts_per_period']:9.4g}  {u['peak_impulse']:10.5g}  "
            f"{q['linear_max_abs_x1']:9.5f}{'  hysteresis' if q['hysteresis'] else ''}"
        )


def _print_lyapunov(r: dict) -> None:
    shown = ", ".join("-inf" if x is None else f"{x:.6g}" for x in r["exponents"])
    errors = ", ".join("-" if x is None else f"{x:.2g}" for x in r["errors"])
    print(f"{r['label']}: exponents per forcing period {shown} (standard errors {errors})")
    print(
        f"  {r['periods']} periods averaged after {r['transient']} + {r['warmup']}; {r['impacts']} impacts, "
        f"{r['captures']} captures, {r['liftoffs']} lift-offs, contact {100 * r['contact_time']:.2f} % of the time "
        f"({r['backend']}{', fallback ' + r['fallback'] if r['fallback'] else ''})"
    )
    (a, b), (ea, eb) = r["halves"], r["half_errors"]
    if ea is not None:
        first, last = r["window"]
        halves = f"largest over periods {first}-{(first + last) // 2} and {(first + last) // 2}-{last}: "
        print(f"  {halves}{a:.4g} +- {ea:.2g} and {b:.4g} +- {eb:.2g}")
    if r["settled_period"] is not None:
        print(f"  settled onto a {r['settled_period']} T cycle from period {r['settled_since']} on")


def _print_design(r: dict) -> None:
    u = r["uncertainty"]
    print(
        f"object: mu = {r['mu']:g}, delta1 = {r['delta1']:g}; band theta {r['band'][0]:g} to {r['band'][1]:g}; "
        f"worst cases over +-{100 * u['detuning']:g} % of omega1, force {u['force'][0]:g} to {u['force'][1]:g} "
        f"times the design force, R +-{u['restitution']:g}; travel limit {r['max_stroke']:.3g} x_st"
    )
    print(
        f"{'device':28s} {'parameters':44s} {'peak':>7s} {'avg':>6s} {'detune':>7s} {'force':>7s} "
        f"{'R':>7s} {'all':>7s} {'stroke':>7s}"
    )
    for d in r["devices"]:
        pars = ", ".join(f"{k} {v:.4g}" for k, v in d["parameters"].items())
        w = d["worst"]
        note = " (TMD limit: never reaches its stop)" if d.get("tmd_limit") else ""
        if d.get("feasible") is False:
            note += " (infeasible: over the travel limit)"
        if d.get("at_bound"):
            note += f" (at a bound: {', '.join(d['at_bound'])})"
        print(
            f"{d['device']:28s} {pars:44s} {d['peak']:7.4f} {d['band_average']:6.3f} {w['detuning']:7.3f} "
            f"{w['force']:7.3f} {w['restitution']:7.3f} {w['together']:7.3f} {d['stroke']:7.2f}{note}"
        )
    d = r["impact"]
    print(
        f"impact loads ({d['device']}): largest pulse {d['pulse']:.4g} P0/omega1, up to {d['impacts_per_period']:.3g} "
        f"impacts per period ({d['impacts_per_hour']:.4g} per hour at f1 = {r['natural_frequency']:g} Hz), mean "
        f"force {d['mean_force']:.4g} P0, peak contact force {d['contact_force']:.4g} P0 on a stop "
        f"{r['stop_stiffness']:g} times stiffer than c1"
    )
    for s in r["snubber"]:
        print(
            f"snubber: a stop at {s['fraction']:g} of the TMD's stroke raises its peak to {s['peak']:.4f} "
            f"({100 * (s['ratio'] - 1):.0f} % more)"
        )
    sub = r.get("subregions")
    if sub is None:
        print("sub-regions: not checked (--subregions checks every answer against its box's halves)")
    else:
        print(
            f"sub-regions: {sub['halves_searched']} halves searched, {len(sub['lower'])} lower than their row's "
            f"search answer (adopted: {', '.join(sub['adopted']) or 'none'}); every answer now passes: "
            f"{'yes' if sub['passed'] else 'no'}, the closest half {100 * sub['smallest_margin']:+.2f} % "
            f"({sub['smallest_row']}, {sub['smallest_half']})"
        )
    print(r["recommendation"] + f" ({r['elapsed']:.1f} s)")


# Each command's text answer (without --json).
PRINTERS = {
    "alg1": _print_alg1,
    "orbit": _print_orbit,
    "steady": _print_steady,
    "response": _print_response,
    "lyapunov": _print_lyapunov,
    "design": _print_design,
}
