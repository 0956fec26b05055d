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

from dataclasses import dataclass, field
from fnmatch import fnmatch

__all__ = [
    "DEFAULT",
    "IMAGE_SUFFIXES",
    "LABEL_COLUMNS",
    "RECORD_DIRECTORIES",
    "SENSITIVE_LABELS",
    "TIMING_FILES",
    "TOLERANCES",
    "Tolerance",
    "tolerance_of",
]

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


@dataclass(frozen=True)
class Tolerance:
    """How far one record may differ (module docstring)."""

    rtol: float = 1e-8  # round-off of a settled number is ~1e-13; 1e-8 leaves five digits' room
    atol: float = 1e-10  # residuals and differences that are round-off themselves (~1e-12)
    cells: int = 2  # a label may flip this close to a label change
    max_sensitive: float = 0.0  # fraction of points whose label may differ at a sensitive point
    keys: tuple[str, ...] = ()  # CSV columns that match rows (adaptive records)
    matrix: bool = False  # a CSV map: header = column coordinates, first column = row coordinate
    by_name: dict[str, float] = field(default_factory=dict)  # JSON path or macro name -> absolute tolerance
    skip: str = ""  # why the record is not compared (a timing file)
    why: str = ""


DEFAULT = Tolerance(why="a settled result: numbers to rtol 1e-8, no label may differ")

# Per record, first match wins. A fraction of points comes with what the emulated machines
# measured (tools/coarse_record.py writes tests/data/coarse_record/emulation.json).
_MAPS = Tolerance(matrix=True, max_sensitive=0.01, why="a regime map: labels flip in chaotic windows and at boundaries")
_POINTS = Tolerance(max_sensitive=0.02, why="labelled points along a parameter: flips at sensitive points")
_ADAPTIVE = Tolerance(
    keys=("x", "y"), max_sensitive=0.05, why="a map refined where its cells change: flips move the refinement"
)
TOLERANCES: tuple[tuple[str, Tolerance], ...] = (
    ("figures/map_*_curves.csv", DEFAULT),
    ("figures/map_*_settings.json", DEFAULT),
    ("figures/map_*.csv", _MAPS),
    ("figures/claims_map*_refined.csv", _ADAPTIVE),
    ("figures/claims_map*.csv", Tolerance(keys=("x", "y"), max_sensitive=0.03, why=_ADAPTIVE.why)),
    (
        "figures/claims_by_parameter_grid.csv",
        Tolerance(keys=("parameter", "value"), max_sensitive=0.03, why=_ADAPTIVE.why),
    ),
    (
        "figures/sweep_transitions.csv",
        Tolerance(keys=("direction", "before", "after"), max_sensitive=0.1, why="transitions located between labels"),
    ),
    ("figures/sweep_*.csv", _POINTS),
    ("figures/lyapunov_*.csv", _POINTS),
    ("figures/gap_scan.csv", _POINTS),
    ("figures/design_response.csv", _POINTS),
    (
        "figures/claims_by_parameter.csv",
        Tolerance(
            rtol=1e-2,
            keys=("parameter", "claim"),
            max_sensitive=0.1,
            why="interval ends bisected to claims_search.rel_tol",
        ),
    ),
    (
        "paper/generated/claims_*",
        Tolerance(rtol=1e-2, why="interval ends and widths bisected to claims_search.rel_tol"),
    ),
    (
        "figures/claims_*.json",
        Tolerance(rtol=1e-2, why="interval ends, searched distances: to their search's resolution"),
    ),
    (
        "paper/generated/sweep_*",
        Tolerance(rtol=1e-2, why="counts of a sweep's labels and maps' cells: within their sensitive points"),
    ),
    ("paper/generated/lyapunov_*", Tolerance(rtol=1e-2, why="counts of labels: within their sensitive points")),
    ("figures/lyapunov_*.json", Tolerance(rtol=1e-2, why="counts of labels: within their sensitive points")),
    (
        "figures/readme_summary.md",
        Tolerance(rtol=1e-2, why="the README's numbers: counts and intervals as their records"),
    ),
)


def tolerance_of(path: str) -> Tolerance:
    """The tolerance of record ``path`` (relative to the repository, '/' separated)."""
    for pattern, tolerance in TOLERANCES:
        if fnmatch(path, pattern):
            return tolerance
    return DEFAULT
