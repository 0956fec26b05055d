"""The report builds: latexmk compiles paper/report.tex from the committed figures and
generated files with no LaTeX error, no undefined reference or citation, no float too large for
its page and no box overfull by more than a point, into a PDF whose bytes do not depend on the
time of the build, with its figures and tables numbered in the order the text cites them. Its
text (quick tests on the sources, generated numbers and sentences expanded) reads as a paper:
no project vocabulary (targets, acceptance criteria, backends, kernels) or code names, no ASCII
mathematics or generated fragments, no script or path in a caption or the text (the appendix of
provenance maps them), every equation referenced as the report's or the paper's, and every
reference cited and every citation listed."""

import hashlib
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def build(tmp: Path) -> tuple[Path, str]:
    shutil.copytree(ROOT / "paper", tmp / "paper", ignore=shutil.ignore_patterns("build", "report.pdf"))
    shutil.copytree(ROOT / "figures", tmp / "figures")
    env = dict(os.environ, SOURCE_DATE_EPOCH="0", FORCE_SOURCE_DATE="1")
    run = subprocess.run(
        ["latexmk", "-r", "latexmkrc", "-outdir=build", "report.tex"],
        cwd=tmp / "paper",
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    log = (tmp / "paper" / "build" / "report.log").read_text(errors="replace")
    assert run.returncode == 0, run.stdout[-3000:] + log[-3000:]
    return tmp / "paper" / "build" / "report.pdf", log


# Layout the LaTeX log reports: a float taller than the page, and a box overfull by more than
# a point (a line or a float that runs into the margin or the page number).
OVERFULL = re.compile(r"^Overfull \\[hv]box \((-?[\d.]+)pt too (wide|high)\)", re.M)
OVERFULL_TOLERANCE_PT = 1.0


def log_defects(log: str) -> list[str]:
    """The layout defects of a LaTeX log: "Float too large" warnings and boxes overfull by more
    than OVERFULL_TOLERANCE_PT."""
    out = [line for line in log.splitlines() if "Float too large" in line]
    return out + [m.group(0) for m in OVERFULL.finditer(log) if float(m.group(1)) > OVERFULL_TOLERANCE_PT]


def test_log_check_catches_the_layout_defects():
    log = (
        "LaTeX Warning: Float too large for page by 29.30193pt on input line 252.\n"
        "Overfull \\hbox (3.2pt too wide) in paragraph at lines 8--9\n"
        "Overfull \\vbox (0.4pt too high) has occurred while \\output is active\n"
        "Underfull \\hbox (badness 5548) in paragraph at lines 49--49\n"
    )
    assert log_defects(log) == [
        "LaTeX Warning: Float too large for page by 29.30193pt on input line 252.",
        "Overfull \\hbox (3.2pt too wide)",
    ]


@pytest.mark.slow
def test_report_builds_cleanly_and_deterministically(tmp_path):
    pdf, log = build(tmp_path / "a")
    assert not re.search(r"^! ", log, flags=re.M), "LaTeX error"
    assert "undefined" not in log.lower().replace("undefined control", ""), [
        line for line in log.splitlines() if "undefined" in line.lower()
    ][:5]
    assert not log_defects(log), log_defects(log)
    assert_floats_numbered_in_citation_order(pdf.parent / "report.aux")
    pdf2, _ = build(tmp_path / "b")
    assert hashlib.sha256(pdf.read_bytes()).digest() == hashlib.sha256(pdf2.read_bytes()).digest()


# --- The report's text: a paper's prose -----------------------------------------------------
# These read the LaTeX sources (the sections, the report's frame and the generated files the
# report inputs), so they run in the quick suite without building the PDF. Most read the text as
# a reader meets it: each section inlined and each generated macro replaced by its value, with
# mathematics set aside (prose(); what is left must read as words, not as code or ASCII).

PAPER = ROOT / "paper"
# Words of the project's own bookkeeping (targets met, acceptance criteria satisfied, software
# parts and their users) that a paper on mechanics does not use: speed and accuracy are reported
# as results about the methods; the package's software benchmarks live in docs/BENCHMARKS.md.
PROJECT_WORDS = re.compile(
    r"\b(targets?|met|acceptance|satisfied|backends?|kernels?|JIT|where users are|public (batch )?calls?|"
    r"command line|package import|numba's cache)\b",
    re.IGNORECASE,
)
# Code names the text must describe in words. Library functions and workflow rules: any
# \texttt{} holding an underscore is one, unless it is a path (a slash or a dot) or a public
# name of another package that the text cites (SciPy's solve_ivp).
ALLOWED_CODE_NAMES = {"solve_ivp"}
CODE_NAMES = (
    "regime_map_batch",
    "solve_point",
    "settle_row",
    "compiled_warm_up",
    "analytic_minus_located",
    "end_checks",
)
# Mathematics written as ASCII in the prose (outside $...$): a symbol spelled out (Delta0, x_st,
# delta2, P0/c1), an assignment "N = 0.6", a number as 1e-10, "+-", "<=", "->", ">bound".
ASCII_MATH = re.compile(
    r"\b(Delta_?0|x_?st|delta_?[12]|P0|c1|m1|m2|omega|theta)\b"
    r"|\b[A-Za-z]\w*\s*(=|<=|>=)\s*[-+]?\d"
    r"|\b\d+(\.\d+)?[eE][-+]?\d+\b"
    r"|\+-|<=|>=|->|>\s*bound"
)
# A count of nothing written as a digit in a sentence ("0 give different verdicts"), and one
# value said twice over ("satisfied and satisfied", "300 periods per cell (300 after ...").
ZERO_COUNT = re.compile(r"(?:^|[;:,(]\s+|\band\s+|\bof\s+)0 [a-z]{2,}", re.M)
SAID_TWICE = re.compile(
    r"(?<![/\d.])\b(\d[\d.]*|satisfied|missed|yes|no|none) and \1\b(?![/\d])|\b(\d+) periods per cell \(\2 after"
)
# A caption names no script, rule or record: provenance is the appendix's (Table "Where each
# figure and table comes from").
CAPTION_PROVENANCE = re.compile(r"\b(Made|Written|Generated) by\b|workflow/|\.py\b|figures/|generated/", re.I)
# A path of the repository in the running text (the appendix, which maps them, excepted).
PATH = re.compile(r"\b[\w.-]+/[\w./-]*\.(py|json|csv|tex|smk|md|yaml|pdf|png)\b|\b(profiles|workflow|figures)/")
# An equation reference: the report's own are (R1), (R2), ... through \eqref; the paper's are
# "the paper's eq. (n)" (or "its eq. (n)", "eq. (n) of the paper"); a bare "eq. 10" or
# "eq. (4)" is neither.
EQUATION_REFERENCE = re.compile(r"\beqs?\.[~\s]*\(?\d")
PAPERS_EQUATION = re.compile(r"(paper's|its)\s+$")
# The files and sections that map the repository (paths allowed there).
APPENDIX = ("sections/provenance.tex", "generated/provenance_table.tex")


def report_sources() -> list[Path]:
    """The files whose text reaches the PDF: the frame, the sections, the generated inputs."""
    return (
        [PAPER / "report.tex", PAPER / "references.tex"]
        + sorted((PAPER / "sections").glob("*.tex"))
        + sorted((PAPER / "generated").glob("*.tex"))
    )


def strip_comments(tex: str) -> str:
    return re.sub(r"(?<!\\)%.*", "", tex)


def running_text(tex: str) -> str:
    """The text a reader sees, roughly: comments, macro names and the arguments of commands that
    name files, labels or keys removed (a macro's name may say Target; its value may not)."""
    tex = strip_comments(tex)
    tex = re.sub(
        r"\\(label|ref|eqref|cite|input|includegraphics|bibitem|newcommand|renewcommand|"
        r"providecommand|usepackage|documentclass|begin|end)(\[[^\]]*\])?\{[^}]*\}",
        " ",
        tex,
    )
    return re.sub(r"\\[A-Za-z]+", " ", tex)


def braced(tex: str, start: int) -> tuple[str, int]:
    """The balanced-brace group opening at ``tex[start]`` ('{'): its content and the index after it."""
    depth, i = 0, start
    while i < len(tex):
        depth += {"{": 1, "}": -1}.get(tex[i], 0)
        i += 1
        if depth == 0:
            return tex[start + 1 : i - 1], i
    raise ValueError(f"unbalanced braces from {tex[start : start + 60]!r}")


def macro_values() -> dict[str, str]:
    """Every macro the generated files define (all without arguments), by name."""
    values = {}
    for path in sorted((PAPER / "generated").glob("*.tex")):
        tex = strip_comments(path.read_text())
        for m in re.finditer(r"\\newcommand\{\\([A-Za-z]+)\}", tex):
            values[m.group(1)], _ = braced(tex, m.end())
    return values


def expand(tex: str, values: dict[str, str]) -> str:
    """``tex`` with every generated macro replaced by its value (values may use others)."""
    pattern = re.compile(r"\\(" + "|".join(sorted(values, key=len, reverse=True)) + r")(?![A-Za-z])(\{\})?")
    for _ in range(5):
        tex, n = pattern.subn(lambda m: values[m.group(1)], tex)
        if not n:
            break
    return tex


def report_text(exclude_appendix: bool = True) -> dict[str, str]:
    """The report's parts as a reader meets them: each source file whose text reaches the PDF
    (the appendix excepted unless asked; the references, which quote titles, left out), comments
    removed, generated macros expanded."""
    values = macro_values()
    out = {}
    for path in report_sources():
        rel = str(path.relative_to(PAPER))
        if (exclude_appendix and rel in APPENDIX) or rel == "references.tex":
            continue
        if rel.startswith("generated/") and "\\newcommand" in path.read_text():
            continue  # a macro file: its values are read where the text uses them
        tex = strip_comments(path.read_text())
        tex = tex.split(r"\begin{document}")[-1]  # the frame's preamble sets, it does not say
        out[rel] = expand(tex, values)
    return out


MATH = re.compile(
    r"\\begin\{(equation|align|tikzpicture)\*?\}.*?\\end\{\1\*?\}|\$\$.*?\$\$|(?<!\\)\$.*?(?<!\\)\$|\\\[.*?\\\]|\\\(.*?\\\)",
    re.S,
)


def prose(tex: str) -> str:
    """The words of ``tex``: mathematics, labels, references and file arguments set aside,
    commands removed, spacing commands as spaces."""
    tex = MATH.sub(" ", tex.replace(r"\$", "S"))
    tex = re.sub(r"\\(label|ref|eqref|cite|input|includegraphics|path|url|begin|end)(\[[^\]]*\])?\{[^}]*\}", " ", tex)
    tex = re.sub(r"\\[,;:! ]|~", " ", tex)
    tex = re.sub(r"\\[A-Za-z]+\*?", " ", tex)
    return re.sub(r"[{}]", "", tex)


def flat(tex: str) -> str:
    """The words and numbers of ``tex``: like :func:`prose`, but the mathematics kept, its
    delimiters and commands dropped (a count or a value set in math still reads as one)."""
    tex = re.sub(r"\\begin\{(equation|align|tikzpicture)\*?\}.*?\\end\{\1\*?\}", " ", tex, flags=re.S)
    tex = re.sub(r"\\(label|ref|eqref|cite|input|includegraphics|path|url|begin|end)(\[[^\]]*\])?\{[^}]*\}", " ", tex)
    tex = re.sub(r"\\[,;:! ]|~", " ", tex.replace("\\$", "S").replace("$", ""))
    tex = re.sub(r"\\[A-Za-z]+\*?", " ", tex)
    return re.sub(r"[{}]", "", tex)


def captions(tex: str) -> list[str]:
    """The arguments of every \\caption{...} of ``tex``."""
    return [braced(tex, m.end() - 1)[0] for m in re.finditer(r"\\caption\{", tex)]


def findings(pattern: re.Pattern, text: str, where: str) -> list[str]:
    return [f"{where}: ...{text[max(0, m.start() - 50) : m.end() + 30]!r}..." for m in pattern.finditer(text)]


def code_names(tex: str) -> list[str]:
    """The code names in ``tex``: a \\texttt{} holding an underscore (not a path, not an allowed
    name of another package) or a module path, and the names of CODE_NAMES anywhere."""
    tex = strip_comments(tex)
    found = []
    for m in re.finditer(r"\\texttt\{([^}]*)\}", tex):
        name = m.group(1).replace(r"\_", "_")
        module = name.startswith("impactdamper.")  # a module path names code, not a method
        if module or ("_" in name and "/" not in name and "." not in name and name not in ALLOWED_CODE_NAMES):
            found.append(name)
    plain = running_text(tex).replace(r"\_", "_")
    return found + [n for n in CODE_NAMES if n in plain and n not in found]


def test_running_text_has_no_project_vocabulary():
    hits = []
    for rel, text in report_text().items():
        hits += findings(PROJECT_WORDS, prose(text), rel)
        hits += [f"{rel}: code name {n}" for n in code_names(text)]
    assert not hits, "\n".join(hits)


def test_running_text_has_no_ascii_mathematics_nor_generated_fragments():
    hits = []
    for rel, text in report_text().items():
        words, numbers = prose(text), flat(text)
        hits += (
            findings(ASCII_MATH, words, rel) + findings(ZERO_COUNT, numbers, rel) + findings(SAID_TWICE, numbers, rel)
        )
    assert not hits, "\n".join(hits)


def test_captions_name_no_script_and_the_text_no_path():
    hits = []
    for rel, text in report_text().items():
        hits += [f"{rel}: caption {c[:80]!r}..." for c in captions(text) if CAPTION_PROVENANCE.search(c)]
        outside = re.sub(r"\\(label|ref|input|includegraphics|begin|end)(\[[^\]]*\])?\{[^}]*\}", " ", text)
        hits += findings(PATH, outside, rel)
    assert not hits, "\n".join(hits)


def test_equations_are_referenced_as_the_reports_or_the_papers():
    hits, texts = [], report_text()
    for rel, text in texts.items():
        for m in EQUATION_REFERENCE.finditer(text):
            before, after = text[max(0, m.start() - 12) : m.start()], text[m.end() : m.end() + 25]
            if not (PAPERS_EQUATION.search(before) or re.match(r"[\d)\s~,and-]*of the paper", after)):
                hits.append(f"{rel}: ...{before}{m.group()}{after}...")
    labels = set().union(*(re.findall(r"\\label\{(eq:[^}]*)\}", t) for t in texts.values()))
    cited = set().union(*(re.findall(r"\\(?:eq)?ref\{(eq:[^}]*)\}", t) for t in texts.values()))
    hits += [f"equation {label} is numbered but never referenced" for label in sorted(labels - cited)]
    assert labels and not hits, "\n".join(hits)


def test_running_text_checks_catch_the_offences():
    # Each check above must be able to fail: each kind of offence, planted, is found.
    assert PROJECT_WORDS.search(prose(r"against a target of 60~s"))
    assert PROJECT_WORDS.search(prose(r"\paragraph{Acceptance criteria.} The kernels' backend"))
    assert PROJECT_WORDS.search(prose(r"(criterion: satisfied and satisfied)"))
    assert PROJECT_WORDS.search(prose(r"\paragraph{Where users are.} The public batch call"))
    assert not PROJECT_WORDS.search(prose(r"the same optimiser and criterion; the peak criterion"))
    for ascii_math in (
        r"a clearance Delta0 = 4.77 P0/c1, is optimal",
        r"its worst case, delta2 $>$bound/+0.057",
        r"at most 1e-10 of it",
        r"off by up to +-10 per cent",
        r"the gap $x$, N = 0.6 and",
    ):
        assert ASCII_MATH.search(prose(ascii_math)), ascii_math
    for fine in (r"$\Delta_0/x_{\mathrm{st}}=4.77$", r"a 2/1 motion, 4/3 and 0/1", r"Fig.~2, Table~4, (R1)"):
        assert not ASCII_MATH.search(prose(fine)), fine
    assert ZERO_COUNT.search(flat(r"tolerance; $0$ give different verdicts"))
    assert not ZERO_COUNT.search(flat(r"no contact, 0/1, at $z = 0$; $k = 1$, $10.0$ and $0.05$"))
    assert SAID_TWICE.search(flat(r"(criterion: \PerfA{} and \PerfA)".replace(r"\PerfA", "satisfied")))
    assert SAID_TWICE.search(flat(r"a cap of $300$ periods per cell ($300$ after a nonperiodic neighbour)"))
    assert SAID_TWICE.search(flat(r"the worst cases are $5.77$ and $5.77$"))
    assert not SAID_TWICE.search(flat(r"between 3/2 and 4/3, $0.5$ and $0.6$; Lyuminarskiy and Lyuminarskiy"))
    assert CAPTION_PROVENANCE.search(r"The model. Made by \texttt{workflow/scripts/fig2a.py}.")
    assert PATH.search(r"(recorded in \texttt{figures/located\_case.json})".replace("\\_", "_"))
    assert PATH.search(r"a SLURM profile is in \texttt{profiles/slurm/}")
    assert EQUATION_REFERENCE.search("(eq. 10 in relative form)") and EQUATION_REFERENCE.search("of eq.~(4):")
    assert PAPERS_EQUATION.search("the paper's ") and not PAPERS_EQUATION.search("a double root of ")
    assert code_names(r"the driver \texttt{regime\_map\_batch} and the rule compiled\_warm\_up") == [
        "regime_map_batch",
        "compiled_warm_up",
    ]
    assert code_names(r"(\texttt{impactdamper.studies.design.optimum})") == ["impactdamper.studies.design.optimum"]
    assert code_names(r"\texttt{solve\_ivp} made \texttt{figures/sweep\_checks.json} % \texttt{end\_checks}") == []
    assert expand(r"\A{} and \B", {"A": r"$x_{\mathrm{st}}$", "B": r"\A"}) == r"$x_{\mathrm{st}}$ and $x_{\mathrm{st}}$"


def cited_keys(tex: str) -> set[str]:
    tex = re.sub(r"(?<!\\)%.*", "", tex)
    return {k.strip() for group in re.findall(r"\\cite(?:\[[^\]]*\])?\{([^}]*)\}", tex) for k in group.split(",")}


def test_every_reference_is_cited_and_every_citation_defined():
    bib = (PAPER / "references.tex").read_text()
    items = set(re.findall(r"\\bibitem(?:\[[^\]]*\])?\{([^}]*)\}", bib))
    # A bibitem citing the paper ("Ref. [4] of \cite{timofeev2019}") does not count as a citation.
    cited = set().union(*(cited_keys(p.read_text()) for p in report_sources() if p.name != "references.tex"))
    assert items, "no \\bibitem in paper/references.tex"
    assert not items - cited, f"references never cited: {sorted(items - cited)}"
    assert not cited - items, f"citations with no reference: {sorted(cited - items)}"


def assert_floats_numbered_in_citation_order(aux: Path) -> None:
    """Figures and tables are numbered in the order the text first cites them."""
    numbers = dict(re.findall(r"\\newlabel\{((?:fig|tab):[^}]*)\}\{\{([^}]*)\}", aux.read_text()))

    def expand(path: Path) -> str:
        tex = re.sub(r"(?<!\\)%.*", "", path.read_text())
        return re.sub(r"\\input\{(sections/[^}]*)\}", lambda m: expand(PAPER / m.group(1)), tex)

    first = list(dict.fromkeys(re.findall(r"\\ref\{((?:fig|tab):[^}]*)\}", expand(PAPER / "report.tex"))))
    for kind in ("fig", "tab"):
        order = [int(numbers[k]) for k in first if k.startswith(kind) and k in numbers]
        assert order == sorted(order), f"{kind} numbered out of citation order: {order}"
