"""Command line: ``impactdamper {steady,alg1,orbit,response,design,lyapunov} [--PARAM VALUE ...] [--json]``.

The same as ``python -m impactdamper ...``; ``impactdamper`` is the console script the package
installs (pyproject.toml, ``[project.scripts]``).

Every parameter of :class:`impactdamper.Parameters` is a flag (defaults: the paper's reference
case). A bad value exits with status 2 and a one-line message naming the flag; so does a case
beyond what the solver can do (an undamped resonance, a motion too fast for its work bound),
naming the parameter that makes it so. Output that cannot be written (a closed pipe, a full
disk) ends with one line on stderr and status 1.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import logging
import os
import re
import sys

from impactdamper.core.algorithm1 import algorithm1
from impactdamper.analysis.orbits import SEEDS, OrbitError, solve_orbit
from impactdamper.analysis.response import MAX_POINTS, frequency_response
from impactdamper.analysis.point import SweepSettings
from impactdamper.core.parameters import PARAMETER_TABLE, Parameters, most_extreme
from impactdamper.core.validation import MAX_PERIODS_LIMIT, Tolerances
from impactdamper.analysis import lyapunov
from impactdamper.analysis.solve import BACKENDS, lyapunov_spectrum, steady_state
from impactdamper.reporting.progress import progress_bar
from impactdamper.reporting.records import clean

__all__ = ["main", "run", "build_parser", "add_quiet_flag", "PROG"]

# The program's name in --help and in error messages: the console script.
PROG = "impactdamper"

# The flags' help, from the parameter table (one line per parameter).
PARAMETER_HELP = {spec.name: spec.help for spec in PARAMETER_TABLE}


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        # A value such as -1e6 is a number, not an option (argparse knows only -1 and -1.5); so
        # are -1_000, -Infinity and -nan (float() reads them): argparse's "expected one argument"
        # named no cause, now the value reaches the flag's own check.
        self._negative_number_matcher = re.compile(
            r"^-(\d[\d_]*\.?[\d_]*|\.\d[\d_]*)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE
        )

    def error(self, message: str) -> None:  # one line, exit status 2
        if message.endswith("expected one argument"):
            # (A value starting with '-' that is not a number reads as an option.)
            message += ": a value that starts with '-' and is not a number must be given as --flag=VALUE"
        self.exit(2, f"{self.prog}: error: {message}\n")

    def _print_message(self, message: str, file=None) -> None:
        # argparse swallows write errors: --help into a full disk then exited 0 with no output.
        # Let them reach run(), which reports them.
        if message:
            (file or sys.stderr).write(message)


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def add_quiet_flag(parser: argparse.ArgumentParser) -> None:
    """``--quiet``, for a command that shows a progress bar on stderr when stderr is a terminal
    (:func:`impactdamper.reporting.progress.progress_bar`)."""
    parser.add_argument(
        "--quiet", action="store_true", help="no progress bar (one is shown on stderr only when stderr is a terminal)"
    )


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog=PROG, description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    defaults = Parameters()

    def add_parameters(p: argparse.ArgumentParser) -> None:
        g = p.add_argument_group("parameters (defaults: the paper's reference case)")
        for name in Parameters.names():
            g.add_argument(
                _flag(name),
                dest=name,
                type=float,
                default=getattr(defaults, name),
                metavar="X",
                help=f"{PARAMETER_HELP[name]} (default {getattr(defaults, name)})",
            )
        p.add_argument("--json", action="store_true", help="print one JSON object")

    def add_solver_flags(s) -> None:
        """The event-driven solver's start and tolerances (``steady``, and ``orbit``'s seed)."""
        s.add_argument(
            "--state",
            type=float,
            nargs=4,
            metavar=("X1", "X2", "V1", "V2"),
            help="initial (x1, x2, x1', x2') in m, m/s (default: the paper's step 1)",
        )
        s.add_argument("--t0", type=float, default=None, help="start time, s (default 0)")
        s.add_argument("--settle-tol", type=float, default=1e-10, help="relative section mismatch for a settled motion")
        s.add_argument("--max-periods", type=int, default=4000, help="forcing periods before 'nonperiodic'")
        s.add_argument("--max-period-multiple", type=int, default=8, help="largest k tried for T_c = k T")
        s.add_argument("--gap-tol", type=float, default=Tolerances.gap_tol, help="grazing resolution, relative to x_st")
        s.add_argument(
            "--chatter-tol",
            type=float,
            default=Tolerances.chatter_tol,
            help="rebound height (relative to x_st) below which chatter becomes contact",
        )

    steady = sub.add_parser("steady", help="settled motion by Algorithm No. 2 (event-driven, exact flow)")
    add_parameters(steady)
    add_solver_flags(steady.add_argument_group("solver"))
    steady.add_argument(
        "--backend",
        choices=BACKENDS,
        default="auto",
        help="compiled (numba), python (the readable reference) or auto: compiled where numba "
        "imports (default); the JSON says which ran ('backend', 'fallback')",
    )

    alg1 = sub.add_parser("alg1", help="Algorithm No. 1: closed-form one-impact orbit")
    add_parameters(alg1)

    orbit = sub.add_parser(
        "orbit", help="periodic cycle solved directly (Newton shooting), admissibility and Floquet multipliers"
    )
    add_parameters(orbit)
    o = orbit.add_argument_group("orbit")
    o.add_argument(
        "--seed",
        choices=SEEDS,
        default="auto",
        help="alg1: Algorithm No. 1's orbit (reported even if not admissible); simulate: the cycle "
        "steady settles on; auto: alg1 if admissible and stable, else simulate (default)",
    )
    o.add_argument(
        "--period-multiple",
        type=int,
        default=None,
        metavar="K",
        help="solve the seed's cycle repeated to K T (a multiple of its own k)",
    )
    add_solver_flags(orbit.add_argument_group("solver (for --seed simulate)"))

    response = sub.add_parser(
        "response",
        help="frequency response: settled motion against theta by an upward and "
        "a downward sweep, loads, energies, hysteresis, linear response",
    )
    add_parameters(response)
    r = response.add_argument_group("frequency response (the band replaces --theta)")
    r.add_argument("--theta-start", type=float, default=0.5, help="lowest theta = omega/omega1 (default 0.5)")
    r.add_argument("--theta-stop", type=float, default=1.5, help="highest theta (default 1.5)")
    r.add_argument(
        "--points",
        type=int,
        default=21,
        help=f"theta values, equally spaced (default 21, at most {MAX_POINTS}: ~40 ms each)",
    )
    r.add_argument(
        "--settle-tol",
        type=float,
        default=SweepSettings.settle_tol,
        help="relative section mismatch for a settled motion",
    )
    r.add_argument(
        "--max-periods",
        type=int,
        default=SweepSettings.max_periods,
        help="forcing periods a point may simulate before 'nonperiodic'",
    )
    add_quiet_flag(response)

    _add_design(sub, defaults)
    _add_lyapunov_command(sub, add_parameters)
    return parser


def _add_design(sub, defaults: Parameters) -> None:
    """The ``design`` command's flags: the object and band, the uncertainties, the limits and
    loads, each with its documented range."""
    design = sub.add_parser(
        "design",
        help="choose a suppressor: the impact suppressor (gap, N, delta2, R) and the "
        "linear TMD (N, delta2) optimised for one object and band, their worst cases "
        "(detuning, force amplitude, restitution), strokes and loads",
        description=DESIGN_DESCRIPTION,
        epilog=DESIGN_KEYS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    from impactdamper.studies.design.devices import NATURAL_FREQUENCY, RANGES, STOP_STIFFNESS, Uncertainty

    def span(name: str) -> str:
        lo, hi = RANGES[name]
        return f"in [{lo:g}, {hi:g}]"

    u = Uncertainty()
    d = design.add_argument_group("object and band")
    d.add_argument(
        "--theta-start",
        type=float,
        default=0.5,
        help=f"lowest theta = omega/omega1, {span('theta_start')} (default 0.5)",
    )
    d.add_argument(
        "--theta-stop",
        type=float,
        default=1.5,
        help=f"highest theta, {span('theta_stop')}, the band {span('band_width')} wide (default 1.5)",
    )
    d.add_argument(
        "--mu", type=float, default=defaults.mu, help=f"{PARAMETER_HELP['mu']}, {span('mu')} (default {defaults.mu})"
    )
    d.add_argument(
        "--delta1",
        type=float,
        default=defaults.delta1,
        help=f"{PARAMETER_HELP['delta1']}, {span('delta1')} (default {defaults.delta1})",
    )
    r = design.add_argument_group("what the designer does not know exactly")
    r.add_argument(
        "--detuning",
        type=float,
        default=u.detuning,
        help=f"the object's natural frequency uncertain by +- this fraction, {span('detuning')} (default {u.detuning})",
    )
    r.add_argument(
        "--force-low",
        type=float,
        default=u.force[0],
        help=f"lowest force amplitude over the design force, {span('force_low')} (default {u.force[0]})",
    )
    r.add_argument(
        "--force-high",
        type=float,
        default=u.force[1],
        help=f"highest force amplitude over the design force, {span('force_high')} (default {u.force[1]})",
    )
    r.add_argument(
        "--restitution-drift",
        type=float,
        default=u.restitution,
        help=f"R uncertain by +- this, {span('restitution_drift')} (default {u.restitution})",
    )
    o = design.add_argument_group("limits and loads")
    o.add_argument(
        "--max-stroke",
        type=float,
        default=None,
        metavar="S",
        help="travel limit max|x2 - x1|/x_st of the stroke-limited designs, both devices (default: 0.7 times "
        "the optimal TMD's stroke)",
    )
    o.add_argument(
        "--stop-stiffness",
        type=float,
        default=STOP_STIFFNESS,
        help=f"the stop's stiffness over the object's spring c1, for the contact force, {span('stop_stiffness')} "
        f"(default {STOP_STIFFNESS:g})",
    )
    o.add_argument(
        "--natural-frequency",
        type=float,
        default=NATURAL_FREQUENCY,
        help=f"the object's natural frequency f1 in Hz, for impacts per hour, {span('natural_frequency')} "
        f"(default {NATURAL_FREQUENCY:g})",
    )
    o.add_argument(
        "--criterion",
        choices=("peak", "band_average", "detuning", "force", "restitution"),
        default="peak",
        help="which optima the keys impact, tmd and ratio report (default peak; every criterion's are in devices)",
    )
    design.add_argument("--json", action="store_true", help="print one JSON object")
    design.add_argument("--quiet", action="store_true", help="no progress lines on stderr")


def _add_lyapunov_command(sub, add_parameters) -> None:
    """The ``lyapunov`` command: the parameters' flags, the run's lengths, a start, a backend."""
    spectrum = sub.add_parser(
        "lyapunov",
        help="Lyapunov spectrum of the motion (exact tangent map, saltation matrices): exponents with "
        "errors and a label (chaotic, quasi-periodic, periodic, not settled)",
        epilog=LYAPUNOV_KEYS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_parameters(spectrum)
    ly = spectrum.add_argument_group("spectrum")
    for name, default, text in (
        ("periods", lyapunov.DEFAULT_PERIODS, f"forcing periods averaged, a multiple of {lyapunov.DEFAULT_BLOCKS}"),
        ("transient", lyapunov.DEFAULT_TRANSIENT, "periods of motion discarded first"),
        ("warmup", lyapunov.DEFAULT_WARMUP, "periods of the tangent walk discarded next"),
    ):
        ly.add_argument(_flag(name), type=int, default=default, metavar="N", help=f"{text} (default {default})")
    ly.add_argument(
        "--state",
        type=float,
        nargs=4,
        metavar=("X1", "X2", "V1", "V2"),
        help="initial (x1, x2, x1', x2') in m, m/s (default: the paper's step 1)",
    )
    ly.add_argument("--t0", type=float, default=0.0, help="start time, s (default 0)")
    ly.add_argument("--backend", choices=BACKENDS, default="auto", help="who walks (default auto: compiled)")


LYAPUNOV_KEYS = """JSON keys (--json), exponents per forcing period T (log|mu|/k at a period-k orbit):
  exponents, errors, spreads  four exponents, largest first (null: -inf, the directions a capture
                  into persistent contact annihilates), their block standard errors and spreads
  exponents_per_second        the same over T, 1/s
  label           chaotic (largest > significance x error and > zero_band), periodic (largest
                  < 0 likewise), quasi-periodic (largest within zero_band with its error, next
                  negative) or not settled
  significance, zero_band     the label's thresholds
  dimension       4, or 2 once captured; periods, transient, warmup, blocks: the run
  impacts, captures, liftoffs, grazing, contact_time   events and share of time in contact
  method, backend, fallback, parameters"""


DESIGN_DESCRIPTION = """Choose a suppressor for an object of mass ratio mu and damping delta1 over a band of
forcing frequencies: the impact suppressor optimised in gap, N, delta2 and R and the linear
tuned-mass damper (TMD) in N and delta2, by one global search with one budget for both (a
Sobol sample, compass searches, a Nelder-Mead polish, a check that no 2 % move along any axis
lowers the answer), for the nominal peak, the band average, the worst case with the object
detuned, with the force amplitude off its design value, with the restitution drifting, and
under a travel limit. Peaks are the worst branch over the band, located. At most a minute on
two cores within the ranges below; progress lines go to stderr (none with --quiet)."""

DESIGN_KEYS = """JSON keys (--json): band, mu, delta1, uncertainty {detuning, force, restitution}, detuning,
criterion, budget, robust_budget, bounds, tmd_stroke, max_stroke, stop_stiffness,
natural_frequency, settings, elapsed (s), recommendation; devices: every row of the design table,
each with
  device          bare object, tmd_peak, impact_peak_reach (its stop within reach),
                  impact_peak (the whole box), tmd_band_average, impact_band_average_reach,
                  impact_band_average, tmd_detuning, impact_detuning, impact_force,
                  impact_restitution, tmd_stroke, impact_stroke
  parameters      {gap, N, delta2, R} (impact) or {N, delta2} (TMD), relative
  peak            the worst branch's peak of max|x1|/x_st over the band, located
  peak_theta, peak_branch   where, and on which branch
  band_average    mean over the band of the worst motion at each theta
  worst           {detuning, force, restitution, together}: the largest peak over each
                  uncertainty's scenarios and over all together, over the nominal x_st
  stroke          max|x2 - x1|/x_st over the band
  impacts         whether the stop is ever reached (false: the TMD limit, tmd_limit true)
  search          the search's record: value, evaluations, at_bound, check (the 2 % moves)
 and for the impact suppressor also pulse (largest pulse per impact over P0/omega1),
 mean_force (P0), impacts_per_period, impacts_per_hour (at natural_frequency), contact_force
 (peak force over P0 of a linear spring stop of stop_stiffness c1), no_contact_floor;
 stroke-limited rows: max_stroke, feasible.
impact, tmd, tmd_equal_stroke: the rows --criterion picks; ratio: impact over TMD of the
criterion, peak, band_average, worst_case (detuning); snubber: the optimal TMD with a stop within
its travel (fraction of its stroke, peak, ratio to the TMD's)."""


def _parameters(args: argparse.Namespace, parser: argparse.ArgumentParser) -> Parameters:
    try:
        return Parameters(**{name: getattr(args, name) for name in Parameters.names()})
    except ValueError as err:
        _fail(parser, err)


def _fail(parser: argparse.ArgumentParser, err: BaseException, p: Parameters | None = None) -> None:
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
    flag = _flag(name) if name else ""
    prefix = f"argument {flag}: " if flag in parser._option_string_actions else ""
    parser.exit(2, f"{parser.prog}: error: {prefix}{message}\n")


def _given(flag: str, given: list[str]) -> bool:
    return any(a == flag or a.startswith(flag + "=") for a in given)


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
    p = _parameters(args, sub)
    if args.command == "orbit" and args.seed == "alg1":
        # Algorithm No. 1's orbit is found in closed form: there is no start to honour.
        for flag, value in (("--state", args.state), ("--t0", args.t0)):
            if value is not None:
                sub.exit(
                    2,
                    f"{sub.prog}: error: argument {flag}: not allowed with --seed alg1 (Algorithm No. 1's "
                    "orbit is closed-form, it has no start); use --seed simulate to start from it\n",
                )
    given = sys.argv[1:] if argv is None else argv
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
    printer = {
        "alg1": _print_alg1,
        "orbit": _print_orbit,
        "steady": _print_steady,
        "response": _print_response,
        "lyapunov": _print_lyapunov,
    }[args.command]
    # A failed point shows as such in the output (label err); its warning is not printed too.
    logging.getLogger("impactdamper").addHandler(logging.NullHandler())
    try:
        if args.command == "response":
            settings = SweepSettings(
                settle_tol=args.settle_tol,
                max_periods=args.max_periods,
                max_periods_after_nonperiodic=min(SweepSettings.max_periods_after_nonperiodic, args.max_periods),
            )
            # Two sweeps (up and down) of `points` settled motions each.
            total = 2 * args.points if args.points > 0 else None
            with progress_bar(total, "response", quiet=args.quiet) as bar:
                result = frequency_response(
                    p, args.theta_start, args.theta_stop, args.points, settings=settings, on_point=bar.step
                ).to_dict()
        elif args.command == "alg1":
            result = algorithm1(p).to_dict()
        elif args.command == "lyapunov":
            run = dict(periods=args.periods, transient=args.transient, warmup=args.warmup, t0=args.t0)
            result = lyapunov_spectrum(p, **run, state=args.state, backend=args.backend).to_dict()
        else:
            solver = dict(
                t0=0.0 if args.t0 is None else args.t0,
                state=args.state,
                tolerances=Tolerances(gap_tol=args.gap_tol, chatter_tol=args.chatter_tol),
                settle_tol=args.settle_tol,
                max_periods=args.max_periods,
                max_period_multiple=args.max_period_multiple,
            )
            if args.command == "orbit":
                result = solve_orbit(p, args.seed, period_multiple=args.period_multiple, **solver).to_dict()
            else:
                s = steady_state(p, **solver, backend=args.backend)
                result = {**s.to_dict(), "method": s.method, "backend": s.backend, "fallback": s.fallback}
    except OrbitError as err:  # Newton failed, or Algorithm No. 1 has no orbit: not a usage error
        print(f"{sub.prog}: {' '.join(str(err).split())}", file=sys.stderr)
        return 1
    except (ValueError, RuntimeError, ArithmeticError) as err:
        # Bad values (ValueError, TypeError through ArgumentTypeError) and work bounds
        # (SearchLimitError is a RuntimeError), each naming its parameter; a numerical failure
        # that names none (never expected) is still one line, naming the likeliest cause.
        _fail(sub, err, p)
    if args.json:
        text = json.dumps(clean(result)) + "\n"
    else:
        buffer = io.StringIO()
        with contextlib.redirect_stdout(buffer):
            printer(result)
        text = buffer.getvalue()
    if sys.stdout is None:  # started with stdout closed (``>&-``): nowhere to write
        return _output_failed(OSError(9, "standard output is closed"))
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except OSError as err:
        return _output_failed(err)
    return 0


def _design(args: argparse.Namespace, sub: argparse.ArgumentParser) -> int:
    """``design``: the design table (:func:`impactdamper.studies.design.optimum.design_optima`);
    progress on stderr at least every 10 s (none with --quiet), one line for a bad value."""
    import time
    import warnings

    from impactdamper.studies.design.devices import Uncertainty
    from impactdamper.studies.design.optimum import design_optima

    start = time.perf_counter()

    def progress(message: str) -> None:
        if not args.quiet:
            print(f"{sub.prog}: [{time.perf_counter() - start:5.1f} s] {message}", file=sys.stderr, flush=True)

    logging.getLogger("impactdamper").addHandler(logging.NullHandler())
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # (a failed point shows in the answer, not as a warning)
            result = design_optima(
                (args.theta_start, args.theta_stop),
                args.mu,
                args.delta1,
                uncertainty=Uncertainty(args.detuning, (args.force_low, args.force_high), args.restitution_drift),
                max_stroke=args.max_stroke,
                criterion=args.criterion,
                stop_stiffness=args.stop_stiffness,
                natural_frequency=args.natural_frequency,
                progress=progress,
            )
    except (ValueError, RuntimeError, ArithmeticError) as err:
        _fail(sub, err)
    if args.json:
        text = json.dumps(clean(result)) + "\n"
    else:
        buffer = io.StringIO()
        with contextlib.redirect_stdout(buffer):
            _print_design(result)
        text = buffer.getvalue()
    if sys.stdout is None:  # started with stdout closed (``>&-``): nowhere to write
        return _output_failed(OSError(9, "standard output is closed"))
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except OSError as err:
        return _output_failed(err)
    return 0


def _one_blas_thread() -> None:
    """One thread in each OpenBLAS loaded (numpy's and scipy's), unless the user set a number.

    The solver's matrices are 4 x 4: BLAS threads never help them, and on a loaded machine the
    thread hand-offs made the matrix-exponential path up to ~90 times slower (tests/conftest.py),
    so that ``steady --theta 1e-9`` took 130 s to reach its work bound instead of 3 s. The
    environment variable must be set before numpy loads, which the package import has done by
    now: set the count in the loaded libraries instead (what threadpoolctl does). Linux only;
    elsewhere, or if anything fails, nothing changes.
    """
    if any(name in os.environ for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")):
        return
    import ctypes

    with contextlib.suppress(OSError):
        with open("/proc/self/maps") as maps:
            paths = {line.split()[-1] for line in maps if "openblas" in line.rsplit("/", 1)[-1].lower()}
        for path in sorted(paths):
            with contextlib.suppress(OSError):
                lib = ctypes.CDLL(path)
                for symbol in (
                    "scipy_openblas_set_num_threads64_",
                    "scipy_openblas_set_num_threads",
                    "openblas_set_num_threads64_",
                    "openblas_set_num_threads",
                ):
                    if hasattr(lib, symbol):
                        getattr(lib, symbol)(1)
                        break


def run(argv: list[str] | None = None) -> int:
    """``impactdamper`` and ``python -m impactdamper``: :func:`main`, and the output flushed, with a write error (a
    closed pipe as in ``| head -c 1``, a full disk) as one line on stderr and status 1 instead of
    a traceback."""
    _one_blas_thread()
    try:
        status = main(argv)
        if sys.stdout is not None:
            sys.stdout.flush()
    except SystemExit as exit_:  # argparse's usage errors and --help; bad values
        status = exit_.code
        try:
            if sys.stdout is not None:
                sys.stdout.flush()
        except OSError as err:
            return _output_failed(err)
    except OSError as err:  # writing the help or the result (nothing else here writes files)
        return _output_failed(err)
    return status


class _Discard(io.TextIOBase):
    """Where output goes once it cannot be written: nowhere, without further errors."""

    def write(self, text: str) -> int:
        return len(text)


def _output_failed(err: OSError) -> int:
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
    print(r["recommendation"] + f" ({r['elapsed']:.1f} s)")
