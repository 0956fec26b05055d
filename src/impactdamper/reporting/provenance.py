"""Where each figure, table and number of the report comes from: the report's appendix that maps
a figure or table, and each file of numbers the text quotes, to the workflow rule that writes
it, that rule's script and the records the script reads, and the report's author line and
locator from the project's citation metadata.

The rules come from the workflow itself: the Snakefile hands them to its provenance rule as
plain data (:class:`Rule`: name, script, output patterns, data-input patterns), so the appendix
is the workflow's own map, not a list kept by hand. The floats and the macros they use come from
the report's sources. Nothing here imports Snakemake.

Replication and extension of Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100.
"""

from __future__ import annotations

import re
import subprocess
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import PurePosixPath

__all__ = [
    "Float",
    "rules_from_data",
    "floats",
    "macro_homes",
    "inline_sections",
    "float_rows",
    "number_rows",
    "compact_rows",
    "compact_table",
    "source_commit",
    "citation_macros",
    "ARCHIVE",
]

# Records a reader of the archive can open: committed data files (results/ is not committed).
RECORD_PREFIX = "figures/"
RECORD_SUFFIXES = (".json", ".csv", ".npz")
# Records the workflow writes but the repository does not commit (timings change from run to run).
UNCOMMITTED_PREFIX = "results/benchmarks/"
# Where the report is not located by a URL in the citation metadata.
ARCHIVE = "the archive accompanying this report"


@dataclass(frozen=True)
class _Rule:
    """A workflow rule as the appendix needs it.

    Attributes
    ----------
    name : str
        The rule's name.
    script : str or None
        Its script, relative to the repository (None for a rule without one).
    outputs : tuple of str
        Its output patterns (``figures/fig2a_{case}.pdf``, ``{case,stated|located}`` allowed).
    inputs : tuple of str
        Its data-input patterns (records it reads; library files and scripts left out).
    """

    name: str
    script: str | None
    outputs: tuple[str, ...]
    inputs: tuple[str, ...] = ()


def rules_from_data(data: Iterable[Mapping]) -> list[_Rule]:
    """The rules from the workflow's plain data (dicts with ``name``, ``script``, ``outputs``,
    ``inputs``), in order."""
    return [_Rule(d["name"], d.get("script"), tuple(d.get("outputs", ())), tuple(d.get("inputs", ()))) for d in data]


_WILDCARD = re.compile(r"\{(\w+)(?:,([^{}]*(?:\{[^{}]*\}[^{}]*)*))?\}")


def _pattern(pattern: str) -> re.Pattern:
    """A regular expression matching the paths of an output pattern, one named group per
    wildcard (its constraint where the pattern gives one)."""
    out, pos, seen = [], 0, set()
    for m in _WILDCARD.finditer(pattern):
        out.append(re.escape(pattern[pos : m.start()]))
        name, constraint = m.group(1), m.group(2)
        out.append(f"(?P={name})" if name in seen else f"(?P<{name}>{constraint or '.+'})")
        seen.add(name)
        pos = m.end()
    out.append(re.escape(pattern[pos:]))
    return re.compile("".join(out) + r"\Z")


def _producer(rules: Sequence[_Rule], path: str) -> tuple[_Rule, dict[str, str]] | None:
    """The rule that writes ``path`` and its wildcards there, or None where no rule does (a
    source file)."""
    for rule in rules:
        for pattern in rule.outputs:
            m = _pattern(pattern).match(path)
            if m:
                return rule, m.groupdict()
    return None


def _fill(pattern: str, wildcards: Mapping[str, str]) -> str | None:
    """``pattern`` with its wildcards filled, or None where one is not known."""
    try:
        return _WILDCARD.sub(lambda m: wildcards[m.group(1)], pattern)
    except KeyError:
        return None


def _committed_records(rule: _Rule, wildcards: Mapping[str, str], exclude: Iterable[str] = ()) -> list[str]:
    """The committed records of a rule's job (its data inputs and outputs under figures/),
    without ``exclude`` (the float's own files), in order and once each."""
    paths = [_fill(p, wildcards) for p in (*rule.inputs, *rule.outputs)]
    skip = set(exclude)
    keep = [p for p in paths if p and p.startswith(RECORD_PREFIX) and p.endswith(RECORD_SUFFIXES) and p not in skip]
    return list(dict.fromkeys(keep))


@dataclass(frozen=True)
class Float:
    """A figure or table of the report: its kind (``fig`` or ``tab``), label, the files it shows
    (figures' PDFs, generated tables) and the macros its body uses (caption left out)."""

    kind: str
    label: str
    files: tuple[str, ...]
    macros: tuple[str, ...] = field(default=())


def inline_sections(tex: str, read) -> str:
    """The report's source with each ``\\input{sections/...}`` replaced by the file's text
    (``read(path)``, a path relative to the report's folder), and each
    ``\\InputIfFileExists{sections/...}{}{}`` likewise where the file exists (``.tex`` added
    where the name has no suffix; nothing where ``read`` raises FileNotFoundError)."""

    def optional(name: str) -> str:
        try:
            return inline_sections(read(name if PurePosixPath(name).suffix else name + ".tex"), read)
        except FileNotFoundError:
            return ""

    tex = re.sub(r"\\InputIfFileExists\{(sections/[^}]*)\}\{\}\{\}", lambda m: optional(m.group(1)), tex)
    return re.sub(r"\\input\{(sections/[^}]*)\}", lambda m: inline_sections(read(m.group(1)), read), tex)


def _strip_comments(tex: str) -> str:
    return re.sub(r"(?<!\\)%.*", "", tex)


def _without_captions(tex: str) -> str:
    r"""``tex`` with the arguments of its \caption{...} removed (braces balanced)."""
    out, pos = [], 0
    for m in re.finditer(r"\\caption\{", tex):
        if m.start() < pos:
            continue
        out.append(tex[pos : m.start()])
        depth, i = 1, m.end()
        while i < len(tex) and depth:
            depth += {"{": 1, "}": -1}.get(tex[i], 0)
            i += 1
        pos = i
    out.append(tex[pos:])
    return "".join(out)


def floats(tex: str) -> list[Float]:
    """The report's figures and tables in source order (``tex``: the report with its sections
    inlined), one per label: a float environment holding several captions gives each label the
    files included since the label before it (the last label also what follows it, a table's
    body after its caption)."""
    tex = _strip_comments(tex)
    out = []
    for env in re.finditer(r"\\begin\{(figure|table)\*?\}(.*?)\\end\{\1\*?\}", tex, flags=re.S):
        body = env.group(2)
        labels = list(re.finditer(r"\\label\{((fig|tab):[^}]*)\}", body))
        for i, lab in enumerate(labels):
            start = labels[i - 1].end() if i else 0
            end = len(body) if i + 1 == len(labels) else lab.start()
            part = _without_captions(body[start:end])
            files = [
                str(PurePosixPath(p).relative_to("..")) if p.startswith("../") else f"paper/{p}"
                for p in re.findall(r"\\(?:includegraphics(?:\[[^\]]*\])?|input)\{([^}]*)\}", part)
            ]
            names = re.findall(r"\\([A-Za-z]+)", part)
            out.append(Float(lab.group(2), lab.group(1), tuple(files), tuple(dict.fromkeys(names))))
    return out


def macro_homes(generated: Mapping[str, str]) -> dict[str, str]:
    """Each macro defined in the generated files (path -> text) by name -> the file defining it."""
    homes = {}
    for path, text in generated.items():
        for name in re.findall(r"\\newcommand\{\\([A-Za-z]+)\}", _strip_comments(text)):
            homes.setdefault(name, path)
    return homes


@dataclass(frozen=True)
class _Row:
    """A line of the appendix: what (TeX: a float's reference, a file), the rule, its script and
    the committed records."""

    what: str
    rule: str | None
    script: str | None
    records: tuple[str, ...]


def _sources(files: Iterable[str], macros: Iterable[str], homes: Mapping[str, str]) -> list[str]:
    """The generated or drawn files a float rests on: its own files and the homes of its macros."""
    out = list(files)
    out += [homes[n] for n in macros if n in homes]
    return list(dict.fromkeys(out))


FLOAT_NAMES = {"fig": "Fig.", "tab": "Table"}


def float_rows(rules: Sequence[_Rule], items: Sequence[Float], homes: Mapping[str, str]) -> list[_Row]:
    """One row per float and rule that writes what it shows: its figure files or generated
    tables, or the macro files its table body reads; a float drawn in the source (no file) gets
    a row without a rule."""
    rows = []
    for f in items:
        what = rf"{FLOAT_NAMES[f.kind]}~\ref{{{f.label}}}"
        jobs: dict[str, tuple[_Rule, list[str], list[str]]] = {}
        for path in _sources(f.files, f.macros, homes):
            found = _producer(rules, path)
            if found is None:
                continue
            rule, wildcards = found
            _, shown, records = jobs.setdefault(rule.name, (rule, [], []))
            shown.append(path)
            records += _committed_records(rule, wildcards)
        if not jobs:
            rows.append(_Row(what, None, None, ()))
        for rule, shown, records in jobs.values():
            kept = [r for r in dict.fromkeys(records) if r not in shown]
            rows.append(_Row(what, rule.name, rule.script, tuple(kept)))
    return rows


def number_rows(rules: Sequence[_Rule], macro_files: Iterable[str]) -> list[_Row]:
    """One row per file of macros the text reads (generated ``\\newcommand`` files): the rule
    that writes it, its script and records."""
    rows = []
    for path in macro_files:
        found = _producer(rules, path)
        if found is None:
            continue
        rule, wildcards = found
        rows.append(_Row(_path(path), rule.name, rule.script, tuple(_committed_records(rule, wildcards, [path]))))
    return rows


def _path(path: str) -> str:
    r"""A path set in the appendix: \path{...} (url.sty: breaks at / and ., no escaping)."""
    return rf"\path{{{path}}}"


@dataclass(frozen=True)
class _RuleRow:
    """A line of the compact appendix: a rule, its script, what of the report it writes (TeX:
    floats' references and files of macros) and whether it reads uncommitted records."""

    rule: str
    script: str | None
    parts: tuple[str, ...]
    uncommitted: bool


def compact_rows(rules: Sequence[_Rule], rows: Iterable[_Row]) -> list[_RuleRow]:
    """The appendix's rows (:func:`float_rows`, :func:`number_rows`) gathered by rule, in order of
    first appearance: each rule once, with every part of the report it writes, flagged where the
    rule reads timing records under ``results/benchmarks/`` (not committed)."""
    by_name = {r.name: r for r in rules}
    parts: dict[str, list[str]] = {}
    for row in rows:
        if row.rule is not None:
            parts.setdefault(row.rule, []).append(row.what)
    return [
        _RuleRow(
            name,
            by_name[name].script,
            tuple(dict.fromkeys(whats)),
            any(i.startswith(UNCOMMITTED_PREFIX) for i in by_name[name].inputs),
        )
        for name, whats in parts.items()
    ]


def compact_table(rows: Sequence[_RuleRow], caption: str, label: str) -> str:
    """A table of ``rows`` in two halves side by side: rule (a dagger where it reads uncommitted
    timing records) -> what of the report it writes (and the rule's script where it is not
    ``workflow/scripts/<rule>.py``)."""
    col = r">{\raggedright\arraybackslash}p{%s\linewidth}"
    spec = "@{}" + col % "0.21" + col % "0.24" + "@{\\hspace{0.03\\linewidth}}" + col % "0.21" + col % "0.24" + "@{}"
    head = [r"\toprule", r"rule & what it writes & rule & what it writes \\", r"\midrule"]
    lines = [rf"\begin{{longtable}}{{{spec}}}", rf"\caption{{{caption}}}\label{{{label}}}\\", *head]
    lines += [r"\endfirsthead", r"\caption[]{(continued)}\\", *head, r"\endhead", r"\bottomrule", r"\endfoot"]

    def cells(r: _RuleRow | None) -> str:
        if r is None:
            return "&"
        name = _path(r.rule) + (r"$^\dagger$" if r.uncommitted else "")
        whats = ", ".join(w.replace(r"\path{paper/generated/", r"\path{") for w in r.parts)
        if r.script and r.script != f"workflow/scripts/{r.rule}.py":
            whats += rf" (script {_path(PurePosixPath(r.script).name)})"
        return f"{name} & {whats}"

    half = (len(rows) + 1) // 2
    for i in range(half):
        right = rows[half + i] if half + i < len(rows) else None
        lines.append(rf"{cells(rows[i])} & {cells(right)} \\")
    lines.append(r"\end{longtable}")
    return "\n".join(lines) + "\n"


def source_commit(
    root: str = ".", sources: Sequence[str] = ("src", "workflow", "config", "paper", "CITATION.cff")
) -> dict:
    """The git commit the sources at ``root`` are checked out at, and whether ``sources`` differ
    from it (the generated files under ``paper/generated/`` and the PDF left out): ``commit``
    (None outside a git checkout), ``dirty``."""
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, check=True)
        status = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no", "--", *sources],
            cwd=root,
            capture_output=True,
            text=True,
            check=True,
        )
    except (OSError, subprocess.CalledProcessError):
        return {"commit": None, "dirty": False}
    changed = [
        line[3:]
        for line in status.stdout.splitlines()
        if not line[3:].startswith(("paper/generated/", "paper/report.pdf"))
    ]
    return {"commit": head.stdout.strip(), "dirty": bool(changed)}


def _tex_text(text: str) -> str:
    """Plain text in TeX (the specials of names and URLs escaped)."""
    return re.sub(r"([&%#_$])", r"\\\1", str(text))


def citation_macros(cff: Mapping, source: Mapping | None = None) -> str:
    """The report's author line, version and locator from the project's citation metadata
    (CITATION.cff read as a mapping): ``\\ReportAuthors``, ``\\ReportVersion``,
    ``\\ReportLocator`` (the repository's URL where the metadata gives one, else "the archive
    accompanying this report"); and the commit the report was built from (``source``, of
    :func:`source_commit`): ``\\ReportCommit`` (12 digits) and ``\\ReportCommitText`` (the
    commit, "with changes to its sources" where they differ from it)."""

    def name(a: Mapping) -> str:
        if "name" in a:
            return str(a["name"])
        return " ".join(str(a[k]) for k in ("given-names", "family-names") if k in a)

    authors = [name(a) for a in cff.get("authors", [])]
    joined = authors[0] if len(authors) == 1 else ", ".join(authors[:-1]) + " and " + authors[-1]
    url = cff.get("repository-code") or cff.get("repository") or cff.get("url")
    locator = rf"\url{{{url}}}" if url else ARCHIVE
    lines = [
        "% The report's author line and locator, from CITATION.cff. Generated by workflow/scripts/provenance.py; do not edit.",
        rf"\newcommand{{\ReportAuthors}}{{{_tex_text(joined)}}}",
        rf"\newcommand{{\ReportVersion}}{{{_tex_text(cff.get('version', ''))}}}",
        rf"\newcommand{{\ReportLocator}}{{{locator}}}",
    ]
    commit = (source or {}).get("commit")
    short = commit[:12] if commit else "unknown"
    text = rf"commit \texttt{{{short}}}" if commit else "a copy outside version control, commit unknown"
    if commit and source.get("dirty"):
        text += " with changes to its sources not yet committed"
    lines += [rf"\newcommand{{\ReportCommit}}{{{short}}}", rf"\newcommand{{\ReportCommitText}}{{{text}}}"]
    return "\n".join(lines) + "\n"
