"""Command line: ``python -m impactdamper {steady,alg1,orbit} [--PARAM VALUE ...] [--json]``.

Every parameter of :class:`impactdamper.Parameters` is a flag (defaults: the paper's reference
case). A bad value exits with status 2 and a one-line message naming the flag.
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from .algorithm1 import algorithm1
from .orbits import SEEDS, OrbitError, solve_orbit
from .parameters import Parameters
from .simulate import Tolerances
from .steady import steady_state

__all__ = ["main", "build_parser"]

PARAMETER_HELP = {
    "theta": "forcing frequency ratio omega/omega1",
    "mu": "mass ratio m2/m1",
    "N": "frequency ratio omega2/omega1",
    "delta1": "relative damping k1/(2 m1 omega1)",
    "delta2": "relative damping k2/(2 m2 omega1)",
    "R": "coefficient of restitution, in [0, 1]",
    "gap": "initial gap Delta0/x_st",
    "omega": "forcing frequency, rad/s",
    "x_st": "static deflection P0/c1, m",
    "m1": "object mass, kg (a free scale)",
}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit status 2
        self.exit(2, f"{self.prog}: error: {message}\n")


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="python -m impactdamper", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    defaults = Parameters()

    def add_parameters(p: argparse.ArgumentParser) -> None:
        g = p.add_argument_group("parameters (defaults: the paper's reference case)")
        for name in Parameters.names():
            g.add_argument(_flag(name), dest=name, type=float, default=getattr(defaults, name),
                           metavar="X", help=f"{PARAMETER_HELP[name]} (default {getattr(defaults, name)})")
        p.add_argument("--json", action="store_true", help="print one JSON object")

    def add_solver_flags(s) -> None:
        """The event-driven solver's start and tolerances (``steady``, and ``orbit``'s seed)."""
        s.add_argument("--state", type=float, nargs=4, metavar=("X1", "X2", "V1", "V2"),
                       help="initial (x1, x2, x1', x2') in m, m/s (default: the paper's step 1)")
        s.add_argument("--t0", type=float, default=0.0, help="start time, s (default 0)")
        s.add_argument("--settle-tol", type=float, default=1e-10, help="relative section mismatch for a settled motion")
        s.add_argument("--max-periods", type=int, default=4000, help="forcing periods before 'nonperiodic'")
        s.add_argument("--max-period-multiple", type=int, default=8, help="largest k tried for T_c = k T")
        s.add_argument("--gap-tol", type=float, default=Tolerances.gap_tol, help="grazing resolution, relative to x_st")
        s.add_argument("--chatter-tol", type=float, default=Tolerances.chatter_tol,
                       help="rebound height (relative to x_st) below which chatter becomes contact")

    steady = sub.add_parser("steady", help="settled motion by Algorithm No. 2 (event-driven, exact flow)")
    add_parameters(steady)
    add_solver_flags(steady.add_argument_group("solver"))

    alg1 = sub.add_parser("alg1", help="Algorithm No. 1: closed-form one-impact orbit")
    add_parameters(alg1)

    orbit = sub.add_parser("orbit", help="periodic cycle solved directly (Newton shooting), "
                                         "admissibility and Floquet multipliers")
    add_parameters(orbit)
    o = orbit.add_argument_group("orbit")
    o.add_argument("--seed", choices=SEEDS, default="auto",
                   help="alg1: Algorithm No. 1's orbit (reported even if not admissible); simulate: the cycle "
                        "steady settles on; auto: alg1 if admissible and stable, else simulate (default)")
    o.add_argument("--period-multiple", type=int, default=None, metavar="K",
                   help="solve the seed's cycle repeated to K T (a multiple of its own k)")
    add_solver_flags(orbit.add_argument_group("solver (for --seed simulate)"))
    return parser


def _parameters(args: argparse.Namespace, parser: argparse.ArgumentParser) -> Parameters:
    try:
        return Parameters(**{name: getattr(args, name) for name in Parameters.names()})
    except ValueError as err:
        name = str(err).split("`")[1] if "`" in str(err) else ""
        parser.exit(2, f"{parser.prog}: error: argument {_flag(name)}: {err}\n")


def _clean(obj):
    """JSON without NaN/inf (they are not JSON): None instead."""
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    return obj


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    sub = parser._subparsers._group_actions[0].choices[args.command]  # for error messages
    p = _parameters(args, sub)
    if args.command == "alg1":
        result = algorithm1(p).to_dict()
        if args.json:
            print(json.dumps(_clean(result)))
        else:
            _print_alg1(result)
        return 0
    if args.command == "orbit":
        try:
            tolerances = Tolerances(gap_tol=args.gap_tol, chatter_tol=args.chatter_tol)
            result = solve_orbit(p, args.seed, period_multiple=args.period_multiple, t0=args.t0, state=args.state,
                                 tolerances=tolerances, settle_tol=args.settle_tol, max_periods=args.max_periods,
                                 max_period_multiple=args.max_period_multiple).to_dict()
        except OrbitError as err:  # Newton failed, or Algorithm No. 1 has no orbit: not a usage error
            print(f"{sub.prog}: {err}", file=sys.stderr)
            return 1
        except ValueError as err:
            name = str(err).split("`")[1] if "`" in str(err) else ""
            sub.exit(2, f"{sub.prog}: error: argument {_flag(name)}: {err}\n")
        if args.json:
            print(json.dumps(_clean(result)))
        else:
            _print_orbit(result)
        return 0
    try:
        tolerances = Tolerances(gap_tol=args.gap_tol, chatter_tol=args.chatter_tol)
        result = steady_state(p, t0=args.t0, state=args.state, tolerances=tolerances,
                              settle_tol=args.settle_tol, max_periods=args.max_periods,
                              max_period_multiple=args.max_period_multiple).to_dict()
    except ValueError as err:
        name = str(err).split("`")[1] if "`" in str(err) else ""
        sub.exit(2, f"{sub.prog}: error: argument {_flag(name)}: {err}\n")
    if args.json:
        print(json.dumps(_clean(result)))
    else:
        _print_steady(result)
    return 0


def _print_alg1(r: dict) -> None:
    if not r["exists"]:
        print(f"Algorithm No. 1: no orbit ({r['reason']})")
        return
    print(f"Algorithm No. 1: impact phase {r['impact_phase']:.12f} T, S = {r['S']:.10g} N s, "
          f"closing velocity {r['velocity']:.10g} m/s")
    if r["negative_gap_intervals"]:
        ivs = ", ".join(f"({a:.6f}, {b:.6f})" for a, b in r["negative_gap_intervals"])
        print(f"  gap negative on {ivs} T after the impact (min {r['min_gap']:.6g} x_st): the orbit is not admissible")
    else:
        print(f"  gap never negative (smallest interior minimum {r['min_gap']:.6g} x_st): admissible")


def _print_steady(r: dict) -> None:
    print(f"regime {r['regime']}, T_c = {r['period_multiple']} T, {r['impacts_per_cycle']} impacts per cycle, "
          f"contact {100 * r['contact_fraction']:.2f} % of the cycle, max |x1|/x_st = {r['x1_max']:.6f} "
          f"({r['periods_simulated']} periods simulated)")
    for i, imp in enumerate(r["impacts"], 1):
        print(f"  t{i} = {imp['t_over_T']:.9f} T (phase {imp['phase']:.9f}), v = {imp['velocity']:.9g} m/s, "
              f"S = {imp['impulse']:.9g} N s")


def _print_orbit(r: dict) -> None:
    _print_steady(r)
    if not r["solved"]:
        print(f"  not solved directly: {r['reason']}")
        return
    print(f"  solved directly (seed {r['seed']}, {r['newton_iterations']} Newton iterations, residual "
          f"{r['residual']:.2g}); admissible: {'yes' if r['admissible'] else 'no, ' + r['reason']}; "
          f"stable: {'yes' if r['stable'] else 'no'}")
    print("  Floquet multipliers |mu|: " + ", ".join(f"{m:.9f}" for m in r["multipliers"]))
