"""The command line's commands run: :func:`main` reads the flags
(:func:`impactdamper.cli.parser.build_parser`), checks what argparse cannot (flags that
contradict each other), computes the command's answer and writes it
(:mod:`impactdamper.cli.output`). A bad value exits with status 2 and one line naming its flag.
"""

from __future__ import annotations

import argparse
import logging
import sys

from impactdamper.analysis.orbits import OrbitError, solve_orbit
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.response import frequency_response
from impactdamper.analysis.solve import lyapunov_spectrum, steady_state
from impactdamper.cli.boundaries import boundaries_answer, print_boundaries
from impactdamper.cli.output import PRINTERS, write_answer
from impactdamper.cli.parser import build_parser, flag
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.core.parameters import Parameters, most_extreme
from impactdamper.core.validation import MAX_PERIODS_LIMIT, Tolerances
from impactdamper.reporting.progress import progress_bar

__all__ = ["main"]

PRINTERS = {**PRINTERS, "boundaries": print_boundaries}


def _parameters(args: argparse.Namespace, parser: argparse.ArgumentParser) -> Parameters:
    try:
        return Parameters(**{name: getattr(args, name) for name in Parameters.names()})
    except ValueError as err:
        _fail(parser, err)


def _fail(parser: argparse.ArgumentParser, err: BaseException, p: Parameters | None = None, args=None) -> None:
    """Exit with status 2 and one line: ``argument --flag:`` and the error, if it names (in
    backticks, like scipy) a parameter that is a flag of this command."""
    message = " ".join(str(err).split())  # one line whatever the error's text
    name = message.split("`")[1] if message.count("`") >= 2 else ""
    if not name and p is not None:
        # A numerical failure that names nothing: name the parameter farthest from the
        # reference case, the usual cause.
        name = most_extreme(p)
        message = (
            f"`{name}` = {getattr(p, name)!r} (the parameter farthest from the reference case) is beyond what "
            f"the solver handles: {type(err).__name__}: {message}"
        )
    option = flag(name) if name else ""
    if option == "--theta" and getattr(args, "theta_start", None) is not None:  # (response: the band sets theta)
        value = message.split("` = ", 1)[1].split(" ", 1)[0] if "` = " in message else ""
        option = "--theta-stop" if value == repr(args.theta_stop) else "--theta-start"
    prefix = f"argument {option}: " if option in parser._option_string_actions else ""
    parser.exit(2, f"{parser.prog}: error: {prefix}{message}\n")


def _given(option: str, given: list[str]) -> bool:
    return any(a == option or a.startswith(option + "=") for a in given)


def _check_period_flags(parser: argparse.ArgumentParser, args: argparse.Namespace, given: list[str]) -> None:
    """--max-periods must exceed --max-period-multiple: name the flag the user gave (``steady
    --max-periods 2`` blamed --max-period-multiple, never given, at its default 8)."""
    periods, multiple = args.max_periods, args.max_period_multiple
    if not (2 <= periods <= MAX_PERIODS_LIMIT and 1 <= multiple < MAX_PERIODS_LIMIT) or multiple < periods:
        return  # (in order, or out of range: the library's own message names the flag)
    if _given("--max-period-multiple", given) and not _given("--max-periods", given):
        parser.exit(
            2,
            f"{parser.prog}: error: argument --max-period-multiple: `max_period_multiple` = {multiple} is "
            f"not allowed: must be an integer in [1, {periods - 1}] (below --max-periods = {periods})\n",
        )
    parser.exit(
        2,
        f"{parser.prog}: error: argument --max-periods: `max_periods` = {periods} is not allowed: must "
        f"exceed --max-period-multiple = {multiple}{'' if _given('--max-period-multiple', given) else ' (its default)'}"
        f", at most {MAX_PERIODS_LIMIT}\n",
    )


def main(argv: list[str] | None = None) -> int:
    """Run one command; returns the exit status (argparse and bad values exit through
    SystemExit with status 2)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    sub = parser._subparsers._group_actions[0].choices[args.command]  # for error messages
    if args.command == "design":
        return _design(args, sub)
    if args.command == "check-record":
        from impactdamper.reporting.recordcheck import check_record_command

        return check_record_command(args.dir, args.against, args.json, sub.prog)
    p = _parameters(args, sub)
    _check_combinations(sub, args, sys.argv[1:] if argv is None else argv)
    if sys.stdout is None:  # started with stdout closed (``>&-``): said before any work
        return write_answer({}, PRINTERS[args.command], True)
    # A failed point shows as such in the output (label err); its warning is not printed too.
    logging.getLogger("impactdamper").addHandler(logging.NullHandler())
    try:
        result = _answer(args, p)
    except OrbitError as err:  # Newton failed, or Algorithm No. 1 has no orbit: not a usage error
        print(f"{sub.prog}: {' '.join(str(err).split())}", file=sys.stderr)
        return 1
    except (ValueError, RuntimeError, ArithmeticError) as err:
        # Bad values (ValueError, TypeError through ArgumentTypeError) and work bounds
        # (SearchLimitError is a RuntimeError), each naming its parameter; a numerical failure
        # that names none (never expected) is still one line, naming the likeliest cause.
        _fail(sub, err, p, args)
    return write_answer(result, PRINTERS[args.command], args.json)


def _check_combinations(sub: argparse.ArgumentParser, args: argparse.Namespace, given: list[str]) -> None:
    """Flags that argparse accepts one by one but not together: a start with ``--seed alg1``,
    periods out of order, ``--theta`` with ``response``'s band (``given``: the command line)."""
    if args.command == "orbit" and args.seed == "alg1":
        # Algorithm No. 1's orbit is found in closed form: there is no start to honour.
        for name, value in (("--state", args.state), ("--t0", args.t0)):
            if value is not None:
                sub.exit(
                    2,
                    f"{sub.prog}: error: argument {name}: not allowed with --seed alg1 (Algorithm No. 1's "
                    "orbit is closed-form, it has no start); use --seed simulate to start from it\n",
                )
    if args.command in ("steady", "orbit"):
        _check_period_flags(sub, args, given)
    if args.command == "response":
        # The band sets theta; a single --theta would be silently unused.
        if any(a == "--theta" or a.startswith("--theta=") for a in given):
            sub.exit(
                2,
                f"{sub.prog}: error: argument --theta: not allowed with response (the band "
                "--theta-start .. --theta-stop sets theta)\n",
            )


def _answer(args: argparse.Namespace, p: Parameters) -> dict:
    """The answer of command ``args.command`` (not ``design``) at the parameters ``p``."""
    if args.command == "response":
        settings = SweepSettings(
            settle_tol=args.settle_tol,
            max_periods=args.max_periods,
            max_periods_after_nonperiodic=min(SweepSettings.max_periods_after_nonperiodic, args.max_periods),
        )
        # Two sweeps (up and down) of `points` settled motions each.
        total = 2 * args.points if args.points > 0 else None
        with progress_bar(total, "response", quiet=args.quiet) as bar:
            return frequency_response(
                p, args.theta_start, args.theta_stop, args.points, settings=settings, on_point=bar.step
            ).to_dict()
    if args.command == "alg1":
        return algorithm1(p).to_dict()
    if args.command == "boundaries":
        return boundaries_answer(args, p)
    if args.command == "lyapunov":
        run = dict(periods=args.periods, transient=args.transient, warmup=args.warmup, t0=args.t0)
        return lyapunov_spectrum(p, **run, state=args.state, backend=args.backend).to_dict()
    solver = dict(
        t0=0.0 if args.t0 is None else args.t0,
        state=args.state,
        tolerances=Tolerances(gap_tol=args.gap_tol, chatter_tol=args.chatter_tol),
        settle_tol=args.settle_tol,
        max_periods=args.max_periods,
        max_period_multiple=args.max_period_multiple,
    )
    if args.command == "orbit":
        return solve_orbit(p, args.seed, period_multiple=args.period_multiple, **solver).to_dict()
    s = steady_state(p, **solver, backend=args.backend)
    return {**s.to_dict(), "method": s.method, "backend": s.backend, "fallback": s.fallback}


def _design(args: argparse.Namespace, sub: argparse.ArgumentParser) -> int:
    """``design``: the design table (:func:`impactdamper.studies.design.optimum.design_optima`);
    progress on stderr at least every 10 s (none with --quiet), one line for a bad value."""
    import time
    import warnings

    from impactdamper.studies.design.devices import Uncertainty
    from impactdamper.studies.design.optimum import check_object, design_optima
    from impactdamper.studies.design.subregions import SUBREGION_BUDGET

    start = time.perf_counter()

    def progress(message: str) -> None:
        if not args.quiet:
            print(f"{sub.prog}: [{time.perf_counter() - start:5.1f} s] {message}", file=sys.stderr, flush=True)

    logging.getLogger("impactdamper").addHandler(logging.NullHandler())
    try:
        uncertainty = Uncertainty(
            args.detuning,
            (args.force_low, args.force_high),
            args.restitution_drift,
            args.stiffness_drift,
            args.damping_drift,
        )
        band = (args.theta_start, args.theta_stop)
        check_object(
            band, args.mu, args.delta1, uncertainty, args.max_stroke, args.stop_stiffness, args.natural_frequency
        )
        if sys.stdout is None:  # started with stdout closed (``>&-``): said before any work
            return write_answer({}, PRINTERS["design"], True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # (a failed point shows in the answer, not as a warning)
            result = design_optima(
                band,
                args.mu,
                args.delta1,
                uncertainty=uncertainty,
                max_stroke=args.max_stroke,
                criterion=args.criterion,
                stop_stiffness=args.stop_stiffness,
                natural_frequency=args.natural_frequency,
                progress=progress,
                workers=args.workers,
                robust=True if args.robust else None,
                subregion_budget=SUBREGION_BUDGET if args.subregions else None,
            )
    except (ValueError, RuntimeError, ArithmeticError) as err:
        _fail(sub, err)
    return write_answer(result, PRINTERS["design"], args.json)
