"""How far a regenerated record may differ from the committed one, record by record: the one
table the reproduction check (``reporting/recordcheck.py``) reads and the README and the report
quote (``python -m impactdamper check-record``).

A record made again on the machine that made it is byte-identical (timings aside). On another CPU
the BLAS kernels (OpenBLAS picks them by CPU) and the compiled kernels (built for the host) round
differently, so a number moves in its last bits, and a discrete result built on numbers flips
where the dynamics are sensitive. The table states, per record (a glob over the record's path):

- ``rtol``, ``atol``: a number reproduces when ``|a - b| <= rtol * max(|a|, |b|) + atol``; a
  number printed with few digits (TeX, Markdown) also within one unit of its last printed digit;
- the labels (every non-numeric cell of a CSV: regime, label, claims' true/false, method) may differ
  only at a sensitive point: either label is one of ``SENSITIVE_LABELS`` (a motion not settled,
  chaotic or not classified, where round-off grows), or the point lies within ``cells`` cells (rows
  of a table in order, cells of a map in rows and columns) of a label change in either record;
  the numbers of a point whose label differs are not compared (another motion), and the count of
  such points must stay within ``max_sensitive`` (a fraction of the record's points);
- an adaptive record (a refined map, a grid refined where it changes, located transitions) has
  rows where its labels change, so a flip adds or removes rows: its rows are matched by ``keys``,
  and the rows in one record only count as sensitive points;
- intervals and searched optima (``by_name``: a JSON key path or a TeX macro name, glob) within
  their method's stated resolution, as an absolute tolerance; counts (of sensitive labels, of
  agreeing checks) within what the sensitive points allow;
- figures (PDF, PNG) are compared through their data files, and timing files are skipped by name
  (``figures/nondeterministic.json`` lists them; ``TIMING_FILES`` adds the timed commands).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fnmatch import fnmatch

__all__ = [
    "BLAS_CORETYPE_OVERRIDE",
    "RECORD_BLAS_CORETYPE",
    "pin_record_blas",
    "COLUMNS",
    "Column",
    "DEFAULT",
    "column_of",
    "IMAGE_SUFFIXES",
    "LABEL_COLUMNS",
    "RECORD_DIRECTORIES",
    "SENSITIVE_KEYS",
    "SENSITIVE_LABELS",
    "SENSITIVE_MARKS",
    "TIMING_FILES",
    "TOLERANCES",
    "tolerance_of",
]

# The OpenBLAS family every workflow job runs (workflow/rules/reproducibility.smk sets
# OPENBLAS_CORETYPE): the routines every x86-64 processor has, so that the record's linear algebra
# is the same bit for bit on any of them; BLAS_CORETYPE_OVERRIDE names another (an emulation).
RECORD_BLAS_CORETYPE = "Prescott"
BLAS_CORETYPE_OVERRIDE = "IMPACTDAMPER_OPENBLAS_CORETYPE"


def pin_record_blas(environ=None) -> str:
    """Set ``OPENBLAS_CORETYPE`` in ``environ`` (default this process's environment, which the
    workflow's jobs inherit) to the record's family, or to the one ``BLAS_CORETYPE_OVERRIDE``
    names (an emulated machine); returns the family set. Before numpy loads, or for children."""
    import os

    environ = os.environ if environ is None else environ
    environ["OPENBLAS_CORETYPE"] = environ.get(BLAS_CORETYPE_OVERRIDE, RECORD_BLAS_CORETYPE)
    return environ["OPENBLAS_CORETYPE"]


# The directories that hold the record, relative to the repository.
RECORD_DIRECTORIES = ("figures", "paper/generated")

# Images are drawn from data files that the check compares; their bytes change with any pixel.
IMAGE_SUFFIXES = (".png", ".pdf")

# Timing records beside those of figures/nondeterministic.json: the README's commands timed from
# a fresh clone (tools/time_commands.py) and the benchmark page.
TIMING_FILES = ("figures/command_times.json", "figures/nondeterministic.json")

# Labels of motions where round-off grows (not settled, chaotic, quasi-periodic, failed): a
# point so labelled in either record may carry another label in the other.
SENSITIVE_LABELS = frozenset(
    {"np", "nonperiodic", "chaotic", "quasi-periodic", "quasiperiodic", "not settled", "failed", "unsettled"}
)


# A table's label columns: a point's label is these cells of its row, and a label changes
# where they change from one row to the next. Any other text that differs (the method that
# settled a point, its start) makes the row differ too, its sensitivity judged by these.
LABEL_COLUMNS = frozenset(
    {"label", "regime", "motion", "stable", "claim_a", "claim_b", "both", "alg1_exists", "alg2_regime", "exists"}
    | {"admissible", "before", "after", "stopped", "one_sided", "claim", "reproduces", "ivp_claim_a", "ivp_claim_b"}
)


# Marks a record prints beside a sensitive result (an interval end that depends on the solver):
# they may come and go with it, so the text is compared without them.
SENSITIVE_MARKS = ("^{\\dagger}",)

# JSON keys that list the sensitive points themselves (the points where two solvers disagree):
# not compared, their count is.
SENSITIVE_KEYS = ("mismatches",)


@dataclass(frozen=True)
class _Tolerance:
    """How far one record may differ (module docstring)."""

    rtol: float = 1e-8  # round-off of a settled number is ~1e-13; 1e-8 leaves five digits' room
    atol: float = 1e-10  # residuals and differences that are round-off themselves (~1e-12)
    cells: int = 2  # a label may flip this close to a label change
    max_sensitive: float = 0.0  # fraction of points whose label may differ at a sensitive point
    keys: tuple[str, ...] = ()  # CSV columns that match rows (adaptive records)
    matrix: bool = False  # a CSV map: header = column coordinates, first column = row coordinate
    by_name: dict[str, float] = field(default_factory=dict)  # JSON path or macro name -> absolute tolerance
    why: str = ""


DEFAULT = _Tolerance(why="a settled result: numbers to rtol 1e-8, no label may differ")

# Per record, first match wins. The fractions of sensitive points are for the full record
# (config/config.yaml: 1,001-point sweeps, 400 x 400 maps), above what a machine of another kind
# gave (issue 49: 15 of 2,002 sweep labels, 304 of 160,400 map cells, 1,423 of 54,571 claims-map
# cells); a coarse record states its own in its tolerances.json (tests/data/coarse_record/).
_MAPS = _Tolerance(
    matrix=True, max_sensitive=0.01, why="a regime map: labels flip in chaotic windows and at boundaries"
)
_POINTS = _Tolerance(max_sensitive=0.02, why="labelled points along a parameter: flips at sensitive points")
_ADAPTIVE = _Tolerance(
    keys=("x", "y"), max_sensitive=0.05, why="a map refined where its cells change: flips move the refinement"
)
_RESOLUTION = "interval ends and searched distances: to their search's resolution (claims_search.rel_tol)"
_COUNTS = "counts of labels and cells: within their sensitive points"
# The located range and the claims beyond the gap (full record): an end is bisected to
# verdict.bisect_tol (1e-3 in the gap) and claims_search.rel_tol, but where a claim flips at a
# sensitive point next to it the bisection takes another path: with another processor's BLAS
# routines (tools/coarse_record.py's emulation, here on the full config) the gap's ends moved by
# one bisection step (7.8e-4) and N's upper end by three bracket widths (1.2e-4); the claims map's
# cells and the reference check's counts by their sensitive points (2 cells of 293, 2 checks).
_ENDS = 1e-3
_LOCATED = {"*range*": _ENDS, "end_checks*.gap": _ENDS, "beyond_the_gap.parameters.*": _ENDS}
_LOCATED |= {"beyond_the_gap.gap.*": _ENDS, "beyond_the_gap.map_both_cells": 10, "beyond_the_gap.reference_check.*": 3}
_LOCATED_WHY = (
    "the located range and the claims beyond the gap: ends to a bisection step, counts within sensitive points"
)
TOLERANCES: tuple[tuple[str, _Tolerance], ...] = (
    ("figures/verdict.json", _Tolerance(by_name=_LOCATED, why=_LOCATED_WHY)),
    ("figures/located_case.json", _Tolerance(by_name=_LOCATED, why=_LOCATED_WHY)),
    (
        "paper/generated/verdict_macros.tex",
        _Tolerance(by_name={"ClaimsMapBothCells": 10, "ClaimsReference*": 3}, why=_LOCATED_WHY),
    ),
    (
        "paper/generated/boundaries_macros.tex",
        _Tolerance(
            by_name={"BoundCpu": math.inf}, why="the boundary curves: their CPU time is a timing, the rest results"
        ),
    ),
    (
        "paper/generated/design_macros.tex",
        _Tolerance(
            by_name={"DesignElapsed": math.inf, "DesignLoadAverage": math.inf},
            why="the design table's wall time and the machine's load while it ran are timings, the rest results",
        ),
    ),
    ("figures/map_*_curves.csv", DEFAULT),
    (
        "figures/map_*_settings.json",
        _Tolerance(
            rtol=0.01,
            by_name={"check.*": 10},
            why="a map's cells computed (they follow its labels, to 1 %) and its brute-force check's counts",
        ),
    ),
    ("figures/map_*.csv", _MAPS),
    ("figures/claims_map*_refined.csv", _ADAPTIVE),
    ("figures/claims_map*.csv", _Tolerance(keys=("x", "y"), max_sensitive=0.03, why=_ADAPTIVE.why)),
    (
        "figures/claims_by_parameter_grid.csv",
        _Tolerance(keys=("parameter", "value"), max_sensitive=0.03, why=_ADAPTIVE.why),
    ),
    (
        "figures/sweep_transitions.csv",
        _Tolerance(
            keys=("direction", "before", "after", "lower"),
            max_sensitive=0.2,
            why="transitions located between labels: a flip next to one moves it to another bracket",
        ),
    ),
    ("figures/sweep_*.csv", _POINTS),
    ("figures/lyapunov_*.csv", _POINTS),
    ("figures/gap_scan.csv", _POINTS),
    ("figures/design_response.csv", _POINTS),
    (
        "figures/claims_by_parameter.csv",
        _Tolerance(rtol=1e-2, keys=("parameter", "claim"), max_sensitive=0.1, why=_RESOLUTION),
    ),
    ("paper/generated/claims_*", _Tolerance(rtol=1e-2, why=_RESOLUTION)),
    (
        "figures/claims_*.json",
        _Tolerance(
            rtol=1e-2,
            by_name={"*refinement*": 4, "*reference_check.cycles": 3, "*solver_dependent_ends*": 2},
            why=_RESOLUTION + "; the reference check's counts and the ends marked solver-dependent, sensitive",
        ),
    ),
    ("paper/generated/sweep_*", _Tolerance(rtol=1e-2, why=_COUNTS)),
    ("paper/generated/lyapunov_*", _Tolerance(rtol=1e-2, why=_COUNTS)),
    ("figures/lyapunov_*.json", _Tolerance(rtol=1e-2, why=_COUNTS)),
    (
        "figures/readme_summary.md",
        _Tolerance(rtol=1e-2, why="the README's numbers: counts and intervals as their records"),
    ),
)


@dataclass(frozen=True)
class Column:
    """A kind of number that carries its own tolerance in every record (a CSV column or a JSON
    key, by name): ``rtol``, ``atol`` as in ``Tolerance``."""

    rtol: float
    atol: float
    why: str
    chatter: bool = False  # at a chattering point (regime chatter, label c/k): not compared
    path: bool = False  # how a point was reached, not a result: not compared


_CHATTER = "a chatter sequence's impacts are counted down to chatter_tol: round-off adds or drops its last ones"
_PATH = "how a chain's point was reached (its start, the method that settled it), not a result"
_SIZE = "a residual or a difference between two methods is round-off or their tolerance: its size kept, not its digits"
# By name (glob), first match wins. Measured on the emulated machines (tools/coarse_record.py).
COLUMNS: tuple[tuple[str, Column], ...] = (
    (
        "*periods",
        Column(0.0, 0.0, "how long a run took to settle: a search path (measured: 240 against 1,245)", path=True),
    ),
    ("nfev", Column(0.0, 0.0, "the cross-check's function evaluations: they follow the run's length", path=True)),
    ("evaluations", Column(0.0, 0.0, "a bisection's or a search's evaluations: its path", path=True)),
    ("*impacts_per_cycle", Column(0.0, 0, _CHATTER, chatter=True)),
    ("z", Column(0.0, 0, _CHATTER, chatter=True)),
    ("velocities", Column(1e-8, 1e-10, _CHATTER, chatter=True)),
    ("[xv][12]_0", Column(0.0, 0.0, _PATH, path=True)),
    ("start", Column(0.0, 0.0, _PATH, path=True)),
    ("method", Column(0.0, 0.0, _PATH, path=True)),
    ("contact_fraction", Column(1e-6, 1e-10, "the part of a cycle in contact, its ends located to the gap tolerance")),
    ("agree", Column(0.0, 3, "checks that agree: within the sensitive points that flip")),
    ("settling", Column(0.0, 3, "checks where a run does not settle: within the sensitive points that flip")),
    ("nonperiodic", Column(0.0, 3, "points not settled: within the sensitive points that flip")),
    ("multiplier", Column(2e-2, 1e-6, "the largest multiplier, from Newton's finite-difference Jacobian of the map")),
    ("*_minus_*", Column(0.5, 1e-9, "a located value minus its closed form: " + _SIZE)),
    ("*mismatch*", Column(0.5, 1e-9, _SIZE)),
    ("basis", Column(0.5, 1e-9, "a verdict's sentence quoting differences between methods: " + _SIZE)),
    ("*difference*", Column(0.5, 1e-9, _SIZE)),
    ("*_diff", Column(0.5, 1e-9, _SIZE)),
    ("*_rel", Column(0.5, 1e-9, _SIZE)),
    ("*residual*", Column(0.5, 1e-9, _SIZE)),
)


def column_of(name: str) -> Column | None:
    """The tolerance of numbers named ``name`` (a CSV column, a JSON key), if they have their own."""
    for pattern, column in COLUMNS:
        if fnmatch(name, pattern):
            return column
    return None


def tolerance_of(path: str) -> _Tolerance:
    """The tolerance of record ``path`` (relative to the repository, '/' separated)."""
    for pattern, tolerance in TOLERANCES:
        if fnmatch(path, pattern):
            return tolerance
    return DEFAULT
