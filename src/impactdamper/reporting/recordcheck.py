"""The reproduction check: a regenerated record against the committed one, file by file, within
the tolerances of ``reporting/record_tolerances.py`` (its docstring says what each allows).

``check_record(new, reference)`` compares every file of the reference's record directories
(``figures/``, ``paper/generated/``) with the same file in ``new`` and returns one ``FileVerdict``
per file (``status`` pass, fail or skip, a one-line ``detail``, the counts behind it); the command
line's ``check-record`` prints them and a summary. A reference is a directory or a git revision of
the repository (``git show REV:path``).
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import subprocess
from dataclasses import dataclass, field, replace
from fnmatch import fnmatch
from pathlib import Path

from .latex import MacroFile, sci
from .record_tolerances import (
    DEFAULT,
    IMAGE_SUFFIXES,
    LABEL_COLUMNS,
    RECORD_DIRECTORIES,
    SENSITIVE_KEYS,
    SENSITIVE_LABELS,
    SENSITIVE_MARKS,
    TIMING_FILES,
    column_of,
    tolerance_of,
)

__all__ = [
    "check_record",
    "emulation_summary",
    "reproducibility_macros",
]


@dataclass
class _Comparison:
    """What one file's comparison found."""

    numbers: int = 0  # numbers that differ (equal text is not counted)
    worst: float = 0.0  # the largest difference relative to its tolerance (<= 1 passes)
    worst_at: str = ""
    points: int = 0  # labelled points (rows, cells)
    sensitive: int = 0  # points whose label differs at a sensitive point (or rows in one record only)
    problems: list[str] = field(default_factory=list)  # each a failure, first shown

    def merge(self, other: _Comparison) -> None:
        self.numbers += other.numbers
        self.problems += other.problems
        if other.worst > self.worst:
            self.worst, self.worst_at = other.worst, other.worst_at

    def number(self, a: float, b: float, tol: float, where: str) -> None:
        self.numbers += 1
        if a == b or (math.isnan(a) and math.isnan(b)):
            return
        ratio = abs(a - b) / tol if tol > 0 else math.inf
        if not ratio <= 1.0:
            self.problems.append(f"{where}: {b!r} against {a!r} (tolerance {tol:.3g})")
        if ratio > self.worst or math.isnan(ratio):
            self.worst, self.worst_at = ratio, where


@dataclass
class _FileVerdict:
    path: str
    status: str  # "pass", "fail", "skip"
    detail: str
    numbers: int = 0
    points: int = 0
    sensitive: int = 0
    allowed: int = 0

    def line(self) -> str:
        return f"{self.status.upper():4} {self.path}: {self.detail}"


def _float(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def _number_tol(a: float, b: float, tol, name: str = "") -> float:
    own = column_of(name)
    rtol, atol = (own.rtol, own.atol) if own else (tol.rtol, tol.atol)
    return rtol * max(abs(a), abs(b)) + atol


def _cells(a: str, b: str, tol, comparison: _Comparison, where: str, name: str = "", chatter=False) -> bool:
    """Compare two cells (column ``name``; ``chatter``: of a chattering point); True when they
    are labels that differ (or a chatter sequence's count)."""
    if a == b:
        return False
    xs, ys = a.split(";"), b.split(";")  # a cell may hold a list of numbers (velocities)
    numbers = [(_float(x), _float(y)) for x, y in zip(xs, ys)]
    if any(x is None or y is None for x, y in numbers):
        return True
    if chatter and _own(name, "chatter"):
        return False  # a chatter sequence's count or velocities: not compared
    if len(xs) != len(ys):
        return True
    for (x, y), ta, tb in zip(numbers, xs, ys):
        unit = (1 + 1e-9) * max(_printed(ta)[1], _printed(tb)[1])  # printed to fewer digits
        comparison.number(x, y, max(_number_tol(x, y, tol, name), unit), where)
    return False


def _own(name: str, flag: str) -> bool:
    own = column_of(name)
    return own is not None and getattr(own, flag)


def _sensitive(labels_a, labels_b, where, neighbours) -> bool:
    """A differing point is sensitive when either label is a sensitive one, or the reference's
    label changes within the stated cells (a boundary that moved; a new island of another label
    in a region of one label is not sensitive)."""
    if set(labels_a[where]) & SENSITIVE_LABELS or set(labels_b[where]) & SENSITIVE_LABELS:
        return True
    return any(n in labels_a and labels_a[n] != labels_a[where] for n in neighbours(where))


def _read_csv(text: str) -> list[list[str]]:
    return list(csv.reader(io.StringIO(text)))


def _compare_rows(ref, new, header, tol, comparison, positions) -> None:
    """Rows matched in order (``positions``: their coordinates for the neighbourhood). A row whose
    labels or text differ is a label difference; a row not settled in either record (a sensitive
    label) has its numbers left out, and so has a start handed on from such a row."""
    labels_a, labels_b, differ, moved = {}, {}, [], {}
    for pos, ra, rb in zip(positions, ref, new):
        row = _Comparison()
        chatter = any(c == "chatter" or c.startswith("c/") for c in ra + rb)
        labels_a[pos] = tuple(c for c, name in zip(ra, header) if name in LABEL_COLUMNS)
        labels_b[pos] = tuple(c for c, name in zip(rb, header) if name in LABEL_COLUMNS)
        unsettled = bool(set(labels_a[pos] + labels_b[pos]) & SENSITIVE_LABELS)
        diff = [
            i
            for i, (a, b) in enumerate(zip(ra, rb))
            if not _own(header[i], "path") and _cells(a, b, tol, row, f"row {pos} {header[i]}", header[i], chatter)
        ]
        if labels_a[pos] != labels_b[pos] or len(ra) != len(rb) or (diff and not unsettled):
            differ.append(pos)  # another motion: its numbers are not compared
        elif row.problems and not unsettled:
            differ.append(pos)  # the same label, another motion (coexisting): only at a sensitive point
            moved[pos] = row.problems[0]
        elif not unsettled:  # (a motion not settled in both: its numbers are a window's)
            comparison.merge(row)
    comparison.points += len(labels_a)
    cells = tol.cells

    def neighbours(pos):
        if isinstance(pos, tuple):
            i, j = pos
            return [(i + di, j + dj) for di in range(-cells, cells + 1) for dj in range(-cells, cells + 1)]
        return [pos + d for d in range(-cells, cells + 1)]

    for pos in differ:
        if _sensitive(labels_a, labels_b, pos, neighbours):
            comparison.sensitive += 1
        elif pos in moved:
            comparison.problems.append(f"{moved[pos]}, at no sensitive point")
        else:
            comparison.problems.append(f"{pos}: label {labels_b[pos]} against {labels_a[pos]} at no sensitive point")


def _compare_csv(ref_text: str, new_text: str, tol) -> _Comparison:
    comparison = _Comparison()
    ref, new = _read_csv(ref_text), _read_csv(new_text)
    if not ref or not new or ref[0] != new[0] and not tol.matrix:
        comparison.problems.append("header differs" if ref and new else "empty")
        return comparison
    if tol.matrix:
        return _compare_matrix(ref, new, tol, comparison)
    header = ref[0]
    if tol.keys:
        index = [header.index(k) for k in tol.keys if k in header]
        by_key_a = {tuple(r[i] for i in index): r for r in ref[1:]}
        by_key_b = {tuple(r[i] for i in index): r for r in new[1:]}
        common = [k for k in by_key_a if k in by_key_b]
        only = max(len(by_key_a), len(by_key_b)) - len(common)  # a row moved counts once
        comparison.sensitive += only  # rows that a flip added, removed or moved
        comparison.points += only
        rows_a = [by_key_a[k] for k in common]
        rows_b = [by_key_b[k] for k in common]
    else:
        rows_a, rows_b = ref[1:], new[1:]
        if len(rows_a) != len(rows_b):
            comparison.problems.append(f"{len(rows_b) - 1} rows against {len(rows_a) - 1}")
            return comparison
    _compare_rows(rows_a, rows_b, header, tol, comparison, list(range(1, len(rows_a) + 1)))
    return comparison


def _compare_matrix(ref, new, tol, comparison) -> _Comparison:
    """A map: the header's coordinates and the rows' first cells as numbers, the cells as labels."""
    rows_a = [r for r in ref if r and r[0] != ref[0][0]]
    rows_b = [r for r in new if r and r[0] != ref[0][0]]
    if len(ref[0]) != len(new[0]) or len(rows_a) != len(rows_b):
        comparison.problems.append("the map's shape differs")
        return comparison
    for a, b in zip(ref[0][1:] + [r[0] for r in rows_a], new[0][1:] + [r[0] for r in rows_b]):
        _cells(a, b, tol, comparison, "coordinate")
    labels_a = {(i, j): (c,) for i, r in enumerate(rows_a) for j, c in enumerate(r[1:])}
    labels_b = {(i, j): (c,) for i, r in enumerate(rows_b) for j, c in enumerate(r[1:])}
    comparison.points += len(labels_a)
    cells = tol.cells

    def neighbours(pos):
        i, j = pos
        return [(i + di, j + dj) for di in range(-cells, cells + 1) for dj in range(-cells, cells + 1)]

    for pos in labels_a:
        if labels_a[pos] == labels_b.get(pos):
            continue
        if pos in labels_b and _sensitive(labels_a, labels_b, pos, neighbours):
            comparison.sensitive += 1
        else:
            comparison.problems.append(f"cell {pos}: {labels_b.get(pos)} against {labels_a[pos]} at no sensitive point")
    return comparison


def _leaves(value, path=""):
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _leaves(item, f"{path}.{key}" if path else str(key))
    elif isinstance(value, list):
        yield f"{path}[]", len(value)
        for i, item in enumerate(value):
            yield from _leaves(item, f"{path}[{i}]")
    else:
        yield path, value


def _by_name(tol, name: str) -> float | None:
    for pattern, absolute in tol.by_name.items():
        if fnmatch(name, pattern):
            return absolute
    return None


def _compare_json(ref_text: str, new_text: str, tol, skip_keys=()) -> _Comparison:
    comparison = _Comparison()
    a, b = dict(_leaves(json.loads(ref_text))), dict(_leaves(json.loads(new_text)))
    for path, x in a.items():
        if any(k in path for k in SENSITIVE_KEYS):
            continue  # a list of the sensitive points themselves (their count is compared)
        if any(fnmatch(path.split("[")[0].rsplit(".", 1)[-1], k) for k in skip_keys):
            continue
        y = b.get(path, "<missing>")
        numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (x, y))
        extra, name = _by_name(tol, path), path.rsplit(".", 1)[-1].split("[")[0]
        if _own(name, "path"):
            continue  # how a result was reached, not a result
        if numeric:
            tolerance = _number_tol(x, y, tol, name) + (extra or 0.0)
            comparison.number(float(x), float(y), tolerance, path)
        elif isinstance(x, str) and isinstance(y, str) and x != y and extra is None:
            comparison.merge(_compare_line(x, y, tol, path, name))
        elif x != y and extra is None:
            comparison.problems.append(f"{path}: {y!r} against {x!r}")
    return comparison


_NUMBER = re.compile(r"(?<![\w\\])[-+]?\d+(?:,\d{3})*(?:\.\d+)?(?:[eE][-+]?\d+)?")
_MACRO = re.compile(r"\\newcommand\*?\{\\(\w+)\}")


def _printed(token: str) -> tuple[float, float]:
    """A printed number and one unit of its last digit."""
    plain = token.replace(",", "").strip()
    if not re.fullmatch(r"[-+]?\d+(\.\d*)?([eE][-+]?\d+)?", plain):
        return float(plain), 0.0  # nan, inf, 1e300 printed otherwise
    mantissa, _, exponent = plain.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return float(plain), 10.0 ** (int(exponent or 0) - decimals)


def _compare_text(ref_text: str, new_text: str, tol) -> _Comparison:
    """TeX macros, tables and Markdown: the text with its numbers taken out must be the same; each
    number within the tolerance or one unit of its last printed digit (a macro's ``by_name``
    tolerance added)."""
    comparison = _Comparison()
    ref_lines, new_lines = ref_text.splitlines(), new_text.splitlines()
    if len(ref_lines) != len(new_lines):
        comparison.problems.append(f"{len(new_lines)} lines against {len(ref_lines)}")
        return comparison
    for number, (la, lb) in enumerate(zip(ref_lines, new_lines), 1):
        for mark in SENSITIVE_MARKS:
            la, lb = la.replace(mark, ""), lb.replace(mark, "")
        if la == lb:
            continue
        macro = _MACRO.search(la)
        where = macro.group(1) if macro else f"line {number}"
        if _NUMBER.sub("#", la) != _NUMBER.sub("#", lb) and _by_name(tol, where) is not None:
            continue
        comparison.merge(_compare_line(la, lb, tol, where))
    return comparison


def _compare_line(la: str, lb: str, tol, where: str, name: str = "") -> _Comparison:
    """One line of text (or a JSON string): the same words, numbers within their tolerance."""
    comparison = _Comparison()
    if _NUMBER.sub("#", la) != _NUMBER.sub("#", lb):
        comparison.problems.append(f"{where}: text differs")
        return comparison
    extra = _by_name(tol, where) or 0.0
    for ta, tb in zip(_NUMBER.findall(la), _NUMBER.findall(lb)):
        (x, ux), (y, uy) = _printed(ta), _printed(tb)
        comparison.number(x, y, max(_number_tol(x, y, tol, name), (1 + 1e-9) * max(ux, uy)) + extra, where)
    return comparison


class _record_source:
    """The files of a record: a directory, or a git revision of repository ``repo``."""

    def __init__(self, where: str, repo: Path):
        self.repo = Path(repo)
        path = Path(where)
        self.directory = path if path.is_dir() else (self.repo / where if (self.repo / where).is_dir() else None)
        self.revision = None if self.directory is not None else where
        self.name = str(self.directory) if self.directory is not None else f"git {where}"

    def files(self) -> list[str]:
        if self.directory is not None:
            return sorted(
                str(p.relative_to(self.directory))
                for d in RECORD_DIRECTORIES
                if (self.directory / d).is_dir()
                for p in (self.directory / d).rglob("*")
                if p.is_file()
            )
        out = subprocess.run(
            ["git", "ls-tree", "-r", "--name-only", self.revision, "--", *RECORD_DIRECTORIES],
            cwd=self.repo,
            capture_output=True,
            text=True,
        )
        if out.returncode != 0:
            raise ValueError(f"--against: {self.revision!r} is neither a directory nor a git revision of {self.repo}")
        return sorted(out.stdout.split())

    def text(self, path: str) -> str | None:
        if self.directory is not None:
            file = self.directory / path
            return file.read_text() if file.is_file() else None
        out = subprocess.run(["git", "show", f"{self.revision}:{path}"], cwd=self.repo, capture_output=True, text=True)
        return out.stdout if out.returncode == 0 else None


def _timing(repo_texts) -> dict[str, object]:
    """Timing files and columns: figures/nondeterministic.json's, and TIMING_FILES."""
    text = repo_texts("figures/nondeterministic.json")
    listed = json.loads(text)["files"] if text else {}
    out = {path: entry["timing_columns"] for path, entry in listed.items()}
    out = {p: ("all" if isinstance(c, str) else c) for p, c in out.items()}
    return {**out, **dict.fromkeys(TIMING_FILES, "all")}


def _compare_file(path: str, ref_text: str, new_text: str, timing_columns=(), overrides=None) -> _FileVerdict:
    """One file's verdict (``overrides``: {record: {field: value}} over the table's tolerance)."""
    tol = tolerance_of(path)
    if overrides and path in overrides:
        tol = replace(tol, **overrides[path])
    if ref_text == new_text:
        return _FileVerdict(path, "pass", "identical")
    if path.endswith(".csv"):
        comparison = _compare_csv(_drop_columns(ref_text, timing_columns), _drop_columns(new_text, timing_columns), tol)
    elif path.endswith(".json"):
        comparison = _compare_json(ref_text, new_text, tol, timing_columns)
    else:
        comparison = _compare_text(ref_text, new_text, tol)
    allowed = math.floor(tol.max_sensitive * comparison.points)
    if comparison.sensitive > allowed:
        comparison.problems.append(
            f"{comparison.sensitive} sensitive points differ, more than {tol.max_sensitive:.1%} of {comparison.points}"
        )
    status = "fail" if comparison.problems else "pass"
    detail = (
        f"{comparison.numbers} numbers differ (the worst by {comparison.worst:.2g} of its tolerance, rtol {tol.rtol:g})"
    )
    if comparison.points:
        detail += (
            f"; {comparison.sensitive} of {comparison.points} points differ at sensitive points (at most {allowed})"
        )
    if comparison.problems:
        more = len(comparison.problems) - 1
        detail = f"{comparison.problems[0]}" + (f" (and {more} more)" if more else "") + "; " + detail
    return _FileVerdict(path, status, detail, comparison.numbers, comparison.points, comparison.sensitive, allowed)


def _drop_columns(text: str, columns) -> str:
    rows = _read_csv(text)
    if not rows or not columns:
        return text
    keep = [i for i, name in enumerate(rows[0]) if name not in columns]
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows([[r[i] for i in keep if i < len(r)] for r in rows])
    return out.getvalue()


def check_record(
    new: str | Path, reference: str = "HEAD", repo: str | Path = ".", overrides=None
) -> list[_FileVerdict]:
    """Every file of ``reference``'s record compared with ``new``'s (module docstring). A reference
    directory may hold ``tolerances.json`` ({record: {field: value}}, e.g. a coarse record's
    larger fractions of sensitive points), which overrides the table for it."""
    repo = Path(repo)
    if overrides is None and Path(reference).is_dir() and (Path(reference) / "tolerances.json").is_file():
        overrides = json.loads((Path(reference) / "tolerances.json").read_text())["records"]
    new_source, ref_source = _record_source(str(new), repo), _record_source(reference, repo)
    if new_source.directory is None:
        raise ValueError(f"DIR: {new} is not a directory")
    timing = _timing(ref_source.text)
    verdicts = []
    for path in ref_source.files():
        if path.endswith(IMAGE_SUFFIXES):
            verdicts.append(_FileVerdict(path, "skip", "image: compared through its data files"))
            continue
        if timing.get(path) == "all":
            verdicts.append(_FileVerdict(path, "skip", "timing file (figures/nondeterministic.json)"))
            continue
        new_text = new_source.text(path)
        if new_text is None:
            verdicts.append(_FileVerdict(path, "fail", f"missing from {new_source.name}"))
            continue
        columns = timing.get(path, ())
        verdicts.append(_compare_file(path, ref_source.text(path), new_text, tuple(columns), overrides))
    return verdicts


def _summary_line(verdicts: list[_FileVerdict]) -> str:
    counts = {s: sum(v.status == s for v in verdicts) for s in ("pass", "fail", "skip")}
    sensitive = sum(v.sensitive for v in verdicts)
    points = sum(v.points for v in verdicts)
    verdict = "reproduces" if not counts["fail"] else "does NOT reproduce"
    return (
        f"The record {verdict}: {counts['pass']} files pass, {counts['fail']} fail, {counts['skip']} skipped; "
        f"{sensitive} of {points} labelled points differ, all at sensitive points"
        if not counts["fail"]
        else f"The record {verdict}: {counts['pass']} files pass, {counts['fail']} fail, {counts['skip']} skipped"
    )


def check_record_command(new: str, against: str, as_json: bool, prog: str) -> int:
    """The command line's ``check-record``: a line per file and the summary (or JSON); 0 when
    the record reproduces, 1 when a file fails, 2 (one line) for a bad directory or revision."""
    import sys
    from dataclasses import asdict

    try:
        verdicts = check_record(new, against, _repository(new))
    except ValueError as err:
        print(f"{prog}: {err}", file=sys.stderr)
        return 2
    if as_json:
        failed = any(v.status == "fail" for v in verdicts)
        print(
            json.dumps(
                {"reproduces": not failed, "summary": _summary_line(verdicts), "files": [asdict(v) for v in verdicts]},
                indent=1,
            )
        )
    else:
        print("\n".join([v.line() for v in verdicts] + [_summary_line(verdicts)]))
    return 1 if any(v.status == "fail" for v in verdicts) else 0


def _repository(new: str) -> Path:
    """The git repository around directory ``new`` (where a revision is looked up), else '.'."""
    out = subprocess.run(
        ["git", "rev-parse", "--show-toplevel"], cwd=new if Path(new).is_dir() else ".", capture_output=True, text=True
    )
    return Path(out.stdout.strip()) if out.returncode == 0 else Path(".")


def emulation_summary(verdicts: list[_FileVerdict]) -> dict:
    """The counts of one check for a record (tools/coarse_record.py's emulation.json)."""
    return {
        "reproduces": not any(v.status == "fail" for v in verdicts),
        "summary": _summary_line(verdicts),
        "files": len(verdicts),
        "identical": sum(v.detail == "identical" for v in verdicts),
        "failed": sum(v.status == "fail" for v in verdicts),
        "numbers_differ": sum(v.numbers for v in verdicts),
        "sensitive": sum(v.sensitive for v in verdicts),
        "points": sum(v.points for v in verdicts),
        "per_file": {v.path: {"status": v.status, "detail": v.detail} for v in verdicts},
    }


def reproducibility_macros(emulation: dict) -> MacroFile:
    """The report's reproducibility macros: the tolerance table's main figures and what the
    emulated machines gave (``emulation``: tests/data/coarse_record/emulation.json)."""
    runs = emulation["runs"]
    macros = MacroFile(["% The reproduction check's tolerances and the emulated machines (tools/coarse_record.py)."])
    macros.add("ReproRtol", sci(DEFAULT.rtol, 0))
    macros.add("ReproAtol", sci(DEFAULT.atol, 0))
    macros.add("ReproCells", str(DEFAULT.cells))
    for name, path in (("Map", "figures/map_theta.csv"), ("Sweep", "figures/sweep_gap.csv")):
        macros.add(f"Repro{name}Bound", f"{100 * tolerance_of(path).max_sensitive:g}")
    macros.add(
        "ReproClaimsMapBound", f"{100 * tolerance_of('figures/claims_map_theta_gap_refined.csv').max_sensitive:g}"
    )
    macros.add("ReproFamilies", " and ".join(runs), text=" and ".join(runs))
    macros.add("ReproReferenceKernels", "/".join(emulation["reference_openblas"]))
    macros.add("ReproRecordFiles", str(max(r["files"] for r in runs.values())))
    macros.add("ReproRecordPoints", f"{max(r['points'] for r in runs.values()):,}".replace(",", "{,}"))
    macros.add("ReproRunsPassed", str(sum(r["reproduces"] for r in runs.values())))
    macros.add("ReproRuns", str(len(runs)))
    macros.add("ReproIdenticalMin", str(min(r["identical"] for r in runs.values())))
    macros.add("ReproSensitiveMin", str(min(r["sensitive"] for r in runs.values())))
    macros.add("ReproSensitiveMax", str(max(r["sensitive"] for r in runs.values())))
    macros.add("ReproNumbersMax", str(max(r["numbers_differ"] for r in runs.values())))
    macros.add("ReproPinnedIdentical", str(emulation["pinned"]["identical"]))
    macros.add("ReproPinnedFiles", str(emulation["pinned"]["files"]))
    return macros
