"""The report builds: latexmk compiles paper/report.tex from the committed figures and
generated files with no LaTeX error, no undefined reference or citation, and no overfull box,
into a PDF whose bytes do not depend on the time of the build, with its figures and tables
numbered in the order the text cites them. Its text (quick tests on the sources) uses no project
vocabulary ("target", "met", code names) and cites every reference it lists, and lists every one
it cites."""

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


@pytest.mark.slow
def test_report_builds_cleanly_and_deterministically(tmp_path):
    pdf, log = build(tmp_path / "a")
    assert not re.search(r"^! ", log, flags=re.M), "LaTeX error"
    assert "undefined" not in log.lower().replace("undefined control", ""), [
        line for line in log.splitlines() if "undefined" in line.lower()
    ][:5]
    assert "Overfull" not in log, [line for line in log.splitlines() if "Overfull" in line][:5]
    assert_floats_numbered_in_citation_order(pdf.parent / "report.aux")
    pdf2, _ = build(tmp_path / "b")
    assert hashlib.sha256(pdf.read_bytes()).digest() == hashlib.sha256(pdf2.read_bytes()).digest()


# --- The report's text: no project vocabulary, every reference cited -------------------------
# These read the LaTeX sources (the sections, the report's frame and the generated files the
# report inputs), so they run in the quick suite without building the PDF.

PAPER = ROOT / "paper"
# Words of the project's own bookkeeping that a paper does not use as judgements: an acceptance
# criterion is stated once as the study's own, and its outcome is "satisfied" or "missed".
PROJECT_WORDS = re.compile(r"\b(targets?|met)\b", re.IGNORECASE)
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


def report_sources() -> list[Path]:
    """The files whose text reaches the PDF: the frame, the sections, the generated inputs."""
    return (
        [PAPER / "report.tex", PAPER / "references.tex"]
        + sorted((PAPER / "sections").glob("*.tex"))
        + sorted((PAPER / "generated").glob("*.tex"))
    )


def running_text(tex: str) -> str:
    """The text a reader sees, roughly: comments, macro names and the arguments of commands that
    name files, labels or keys removed (a macro's name may say Target; its value may not)."""
    tex = re.sub(r"(?<!\\)%.*", "", tex)
    tex = re.sub(
        r"\\(label|ref|eqref|cite|input|includegraphics|bibitem|newcommand|renewcommand|"
        r"providecommand|usepackage|documentclass|begin|end)(\[[^\]]*\])?\{[^}]*\}",
        " ",
        tex,
    )
    return re.sub(r"\\[A-Za-z]+", " ", tex)


def code_names(tex: str) -> list[str]:
    """The code names in ``tex``: a \\texttt{} holding an underscore (not a path, not an allowed
    name of another package) or a module path, and the names of CODE_NAMES anywhere."""
    tex = re.sub(r"(?<!\\)%.*", "", tex)
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
    for path in report_sources():
        raw = path.read_text()
        text = running_text(raw)
        for m in PROJECT_WORDS.finditer(text):
            hits.append(f"{path.relative_to(ROOT)}: ...{text[max(0, m.start() - 40) : m.end() + 20]!r}...")
        hits += [f"{path.relative_to(ROOT)}: code name {n}" for n in code_names(raw)]
    assert not hits, "\n".join(hits)


def test_running_text_check_catches_the_words():
    # The check above must be able to fail: each kind of offence, planted, is found.
    assert PROJECT_WORDS.search(running_text(r"against a target of 60~s"))
    assert PROJECT_WORDS.search(running_text(r"& \PerfCompiledMet{} & met \\"))
    assert not PROJECT_WORDS.search(running_text(r"\PerfSpeedupTarget{} times, criterion satisfied % met"))
    assert code_names(r"the driver \texttt{regime\_map\_batch} and the rule compiled\_warm\_up") == [
        "regime_map_batch",
        "compiled_warm_up",
    ]
    assert code_names(r"(\texttt{impactdamper.studies.design.optimum})") == ["impactdamper.studies.design.optimum"]
    assert code_names(r"\texttt{solve\_ivp} made \texttt{figures/sweep\_checks.json} % \texttt{end\_checks}") == []


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
