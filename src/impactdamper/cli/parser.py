"""The command line's flags and help: one parser for every command of
:mod:`impactdamper.cli`, each parameter of :class:`impactdamper.Parameters` a flag with its
table's help, bad usage one line on stderr with status 2."""

from __future__ import annotations

import argparse
import re
import sys

from impactdamper.analysis import lyapunov
from impactdamper.analysis.orbits import SEEDS
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.response import MAX_POINTS
from impactdamper.analysis.solve import BACKENDS
from impactdamper.core.parameters import PARAMETER_TABLE, Parameters
from impactdamper.core.validation import Tolerances

__all__ = ["PROG", "PARAMETER_HELP", "DESCRIPTION", "build_parser", "add_quiet_flag", "flag"]

# The program's name in --help and in error messages: the console script.
PROG = "impactdamper"

# What --help says first (the first line of the package's docstring).
DESCRIPTION = (
    "Command line: ``impactdamper {steady,alg1,orbit,response,design,lyapunov} [--PARAM VALUE ...] [--json]``."
)

# The flags' help, from the parameter table (one line per parameter).
PARAMETER_HELP = {spec.name: spec.help for spec in PARAMETER_TABLE}
# The commands that take the parameters' flags (:func:`_parameter_command`), with their --help lines.
COMMAND_HELP = {
    "steady": "settled motion by Algorithm No. 2 (event-driven, exact flow)",
    "alg1": "Algorithm No. 1: closed-form one-impact orbit",
    "orbit": "periodic cycle solved directly (Newton shooting), admissibility and Floquet multipliers",
    "response": "frequency response: settled motion against theta by an upward and "
    "a downward sweep, loads, energies, hysteresis, linear response",
    "lyapunov": "Lyapunov spectrum of the motion (exact tangent map, saltation matrices): exponents with "
    "errors and a label over the run's window (chaotic, chaotic transient, quasi-periodic, periodic, "
    "not settled)",
    "boundaries": "every boundary of a regime map's plane as curves: folds, period doublings, Neimark-Sacker "
    "points and grazings followed by two-parameter continuation, first contact and lift-off",
}


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


def flag(name: str) -> str:
    """The option of parameter ``name``: ``--max-periods`` for ``max_periods``."""
    return "--" + name.replace("_", "-")


def add_quiet_flag(parser: argparse.ArgumentParser) -> None:
    """``--quiet``, for a command that shows a progress bar on stderr when stderr is a terminal
    (:func:`impactdamper.reporting.progress.progress_bar`)."""
    parser.add_argument(
        "--quiet", action="store_true", help="no progress bar (one is shown on stderr only when stderr is a terminal)"
    )


def _add_state_flag(parser) -> None:
    """The start ``--state`` (x1, x2, x1', x2'), by default the paper's step 1."""
    parser.add_argument(
        "--state",
        type=float,
        nargs=4,
        metavar=("X1", "X2", "V1", "V2"),
        help="initial (x1, x2, x1', x2') in m, m/s (default: the paper's step 1)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The parser of every command (``steady``, ``alg1``, ``orbit``, ``response``, ``design``,
    ``lyapunov``), in that order in --help."""
    parser = _Parser(prog=PROG, description=DESCRIPTION)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    defaults = Parameters()

    steady = _parameter_command(sub, "steady", defaults)
    _add_solver_flags(steady.add_argument_group("solver"))
    steady.add_argument(
        "--backend",
        choices=BACKENDS,
        default="auto",
        help="compiled (numba), python (the readable reference) or auto: compiled where numba "
        "imports (default); the JSON says which ran ('backend', 'fallback')",
    )

    _parameter_command(sub, "alg1", defaults)

    _add_orbit(sub, defaults)
    _add_response(sub, defaults)
    _add_design(sub, defaults)
    _add_lyapunov_command(sub, defaults)
    from impactdamper.cli.boundaries import add_boundaries_flags  # (imports the boundaries' solver)

    add_boundaries_flags(_parameter_command(sub, "boundaries", defaults))
    _add_check_record(sub)
    return parser


def _add_check_record(sub) -> None:
    """``check-record``: a regenerated record against the committed one (reporting/recordcheck.py)."""
    check = sub.add_parser(
        "check-record",
        help="compare a regenerated record (figures/, paper/generated/) with the committed one, "
        "file by file, within the tolerances of reporting/record_tolerances.py; exit 1 if any fails",
    )
    check.add_argument("dir", nargs="?", default=".", help="the regenerated record's root (default: .)")
    check.add_argument("--against", default="HEAD", help="the reference: a git revision or a directory (default: HEAD)")
    check.add_argument("--json", action="store_true", help="the verdicts as JSON")


def _parameter_command(sub, name: str, defaults: Parameters, **kwargs) -> argparse.ArgumentParser:
    """Command ``name`` (its help from :data:`COMMAND_HELP`; ``kwargs`` to ``add_parser``) with
    the parameters' flags (defaults: ``defaults``)."""
    command = sub.add_parser(name, help=COMMAND_HELP[name], **kwargs)
    _add_parameters(command, defaults)
    return command


def _add_parameters(p: argparse.ArgumentParser, defaults: Parameters) -> None:
    """A flag for every parameter (defaults: ``defaults``), and ``--json``."""
    g = p.add_argument_group("parameters (defaults: the paper's reference case)")
    for name in Parameters.names():
        g.add_argument(
            flag(name),
            dest=name,
            type=float,
            default=getattr(defaults, name),
            metavar="X",
            help=f"{PARAMETER_HELP[name]} (default {getattr(defaults, name)})",
        )
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _add_solver_flags(s) -> None:
    """The event-driven solver's start and tolerances (``steady``, and ``orbit``'s seed)."""
    _add_state_flag(s)
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


def _add_orbit(sub, defaults: Parameters) -> None:
    """The ``orbit`` command: the parameters' flags, the seed and its period, the solver's."""
    orbit = _parameter_command(sub, "orbit", defaults)
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
    _add_solver_flags(orbit.add_argument_group("solver (for --seed simulate)"))


def _add_response(sub, defaults: Parameters) -> None:
    """The ``response`` command: the parameters' flags, the band, the settling's caps."""
    response = _parameter_command(sub, "response", defaults)
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
    from impactdamper.studies.design.devices import WORKERS

    _add_design_object(design, defaults)
    _add_design_uncertainty(design)
    _add_design_limits(design)
    design.add_argument(
        "--workers",
        type=int,
        default=WORKERS,
        help=f"worker processes, an integer >= 1 (default {WORKERS}, the cores the minute above is "
        "quoted for); the answer does not depend on them",
    )
    design.add_argument("--json", action="store_true", help="print one JSON object")
    design.add_argument("--quiet", action="store_true", help="no progress lines on stderr")


def _span(name: str) -> str:
    """The documented range of design input ``name``, as help text."""
    from impactdamper.studies.design.devices import RANGES

    lo, hi = RANGES[name]
    return f"in [{lo:g}, {hi:g}]"


def _ranged(group, flag: str, default: float, what: str) -> None:
    """A float flag whose help says what it is, its documented range and its default."""
    help_text = f"{what}, {_span(flag[2:].replace('-', '_'))} (default {default})"
    group.add_argument(flag, type=float, default=default, help=help_text)


def _add_design_object(design, defaults: Parameters) -> None:
    """The ``design`` flags of the object and the frequency band."""
    d = design.add_argument_group("object and band")
    _ranged(d, "--theta-start", 0.5, "lowest theta = omega/omega1")
    d.add_argument(
        "--theta-stop",
        type=float,
        default=1.5,
        help=f"highest theta, {_span('theta_stop')}, the band {_span('band_width')} wide (default 1.5)",
    )
    _ranged(d, "--mu", defaults.mu, PARAMETER_HELP["mu"])
    _ranged(d, "--delta1", defaults.delta1, PARAMETER_HELP["delta1"])


def _add_design_uncertainty(design) -> None:
    """The ``design`` flags of what the designer does not know exactly (the worst cases)."""
    from impactdamper.studies.design.devices import Uncertainty

    u = Uncertainty()
    r = design.add_argument_group("what the designer does not know exactly")
    _ranged(r, "--detuning", u.detuning, "the object's natural frequency uncertain by +- this fraction")
    _ranged(r, "--force-low", u.force[0], "lowest force amplitude over the design force")
    _ranged(r, "--force-high", u.force[1], "highest force amplitude over the design force")
    _ranged(r, "--restitution-drift", u.restitution, "R uncertain by +- this")
    _ranged(
        r, "--stiffness-drift", u.stiffness, "the absorber's spring c2 uncertain by +- this fraction (both devices)"
    )
    _ranged(r, "--damping-drift", u.damping, "the absorber's damper uncertain by +- this fraction (both devices)")


def _add_design_limits(design) -> None:
    """The ``design`` flags of the stroke limit, the loads and which optima are reported."""
    from impactdamper.studies.design.devices import NATURAL_FREQUENCY, STOP_STIFFNESS

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
        help=f"the stop's stiffness over the object's spring c1, for the contact force, {_span('stop_stiffness')} "
        f"(default {STOP_STIFFNESS:g})",
    )
    o.add_argument(
        "--natural-frequency",
        type=float,
        default=NATURAL_FREQUENCY,
        help=f"the object's natural frequency f1 in Hz, for impacts per hour, {_span('natural_frequency')} "
        f"(default {NATURAL_FREQUENCY:g})",
    )
    o.add_argument(
        "--criterion",
        choices=("peak", "band_average", "detuning", "force", "restitution"),
        default="peak",
        help="which optima the keys impact, tmd and ratio report (default peak; every criterion's are in devices)",
    )
    o.add_argument(
        "--robust",
        action="store_true",
        help="search the full robust table (every uncertainty's optimum, every row's worst peaks; a robust "
        "--criterion implies it): slower than the nominal answer (its time: docs/BENCHMARKS.md, the design "
        "table's run)",
    )
    o.add_argument(
        "--subregions",
        action="store_true",
        help="check every answer against its box's halves (each half without the answer searched again; a "
        "lower half is adopted and checked again): about twice the time, beyond the minute; the workflow's "
        "design table runs it (key subregions)",
    )


def _add_lyapunov_command(sub, defaults: Parameters) -> None:
    """The ``lyapunov`` command: the parameters' flags, the run's lengths, a start, a backend."""
    spectrum = _parameter_command(
        sub, "lyapunov", defaults, epilog=LYAPUNOV_KEYS, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ly = spectrum.add_argument_group("spectrum")
    for name, default, text in (
        ("periods", lyapunov.DEFAULT_PERIODS, f"forcing periods averaged, a multiple of {lyapunov.DEFAULT_BLOCKS}"),
        ("transient", lyapunov.DEFAULT_TRANSIENT, "periods of motion discarded first"),
        ("warmup", lyapunov.DEFAULT_WARMUP, "periods of the tangent walk discarded next"),
    ):
        ly.add_argument(flag(name), type=int, default=default, metavar="N", help=f"{text} (default {default})")
    _add_state_flag(ly)
    ly.add_argument("--t0", type=float, default=0.0, help="start time, s (default 0)")
    ly.add_argument("--backend", choices=BACKENDS, default="auto", help="who walks (default auto: compiled)")


LYAPUNOV_KEYS = """JSON keys (--json), exponents per forcing period T (log|mu|/k at a period-k orbit):
  exponents, errors, spreads  four exponents, largest first (null: -inf, the directions a capture
                  into persistent contact annihilates), their block standard errors and spreads
  exponents_per_second        the same over T, 1/s
  label           over the window: chaotic (largest > significance x error and > zero_band, so
                  in both halves, the halves agreeing within significance combined errors, the
                  motion not settled onto a cycle by the end), chaotic transient (largest
                  positive, but settled by the end), periodic (largest < 0 likewise),
                  quasi-periodic (largest within zero_band with its error, next negative) or
                  not settled
  halves, half_errors         the largest exponent over each half of the window, its errors
  settled_period, settled_since   the cycle (k of k T) the motion settled onto by the window's
                  end, and from which period on (null: not settled)
  window          [first, last) period of the averaged window, counted from the start
  significance, zero_band     the label's thresholds
  dimension       4, or 2 once captured; periods, transient, warmup, blocks: the run
  impacts, captures, liftoffs, grazing, contact_time   events and share of time in contact
  method, backend, fallback, parameters"""


DESIGN_DESCRIPTION = """Choose a suppressor for an object of mass ratio mu and damping delta1 over a band of
forcing frequencies: the impact suppressor optimised in gap, N, delta2 and R and the linear
tuned-mass damper (TMD) in N and delta2, by one global search with one budget for both (a
Sobol sample, compass searches, a Nelder-Mead polish, a check that no 2 % move along any axis
lowers the answer; with --subregions, that no half of the box does better), for the nominal peak, the band average, the worst case with the object
detuned, with the force amplitude off its design value, with the restitution drifting, and
under a travel limit. Peaks are the worst branch over the band, located. At most a minute on
two cores within the ranges below; progress lines go to stderr (none with --quiet)."""

DESIGN_KEYS = """JSON keys (--json): band, mu, delta1, uncertainty {detuning, force, restitution, stiffness,
damping}, detuning, criterion, budget, robust_budget, bounds, tmd_stroke, max_stroke, stop_stiffness,
natural_frequency, settings, elapsed (s), longest_silence (s between two progress lines),
recommendation, subregions (with --subregions: budget, rows_count, halves_searched, lower,
adopted, smallest_margin, passed, rows); devices: every row of the design table,
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
