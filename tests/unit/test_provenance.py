"""The report's appendix of provenance: a file is traced to the rule whose output pattern matches
it (wildcards and their constraints honoured), a float to the files it shows and the macros its
body reads, and the records listed are the committed ones of that rule's job."""

from impactdamper.reporting import provenance as pv

RULES = pv.rules_from_data(
    [
        {
            "name": "fig2a",
            "script": "workflow/scripts/fig2a.py",
            "outputs": ["figures/fig2a_{case,stated|located}.pdf", "figures/fig2a_{case,stated|located}.png"],
            "inputs": ["results/compiled/warm_up.json", "figures/fig2a_{case}.csv", "figures/reference_{case}.json"],
        },
        {
            "name": "map_gather",
            "script": "workflow/scripts/map_gather.py",
            "outputs": ["figures/map_{map,theta|damping}.csv", "results/benchmarks/map_{map,theta|damping}.json"],
            "inputs": [],
        },
        {
            "name": "map_curves",
            "script": "workflow/scripts/map_curves.py",
            "outputs": ["figures/map_{map,theta|damping}_curves.csv"],
            "inputs": ["figures/map_{map}.csv"],
        },
        {
            "name": "verdict",
            "script": "workflow/scripts/verdict.py",
            "outputs": ["figures/verdict.json", "results/report/verdict.json", "paper/generated/verdict_macros.tex"],
            "inputs": ["figures/reference_stated.json", "figures/located_case.json"],
        },
        {"name": "all", "script": None, "outputs": [], "inputs": ["figures/verdict.json"]},
    ]
)


def test_a_file_is_traced_to_the_rule_whose_pattern_matches_with_its_wildcards():
    rule, wildcards = pv._producer(RULES, "figures/fig2a_located.pdf")
    assert (rule.name, wildcards) == ("fig2a", {"case": "located"})
    # A constraint keeps a longer name out: map_theta_curves.csv is map_curves', not map_gather's.
    assert pv._producer(RULES, "figures/map_theta_curves.csv")[0].name == "map_curves"
    assert pv._producer(RULES, "figures/map_theta.csv")[0].name == "map_gather"
    assert pv._producer(RULES, "figures/fig2a_other.pdf") is None
    assert pv._producer(RULES, "paper/report.tex") is None


def test_the_records_are_the_jobs_committed_data_files_once_each():
    rule, wildcards = pv._producer(RULES, "figures/fig2a_stated.pdf")
    assert pv._committed_records(rule, wildcards) == ["figures/fig2a_stated.csv", "figures/reference_stated.json"]
    rule, wildcards = pv._producer(RULES, "paper/generated/verdict_macros.tex")
    assert pv._committed_records(rule, wildcards) == [
        "figures/reference_stated.json",
        "figures/located_case.json",
        "figures/verdict.json",
    ]


REPORT = r"""
\begin{figure}[tbp]
\includegraphics[width=0.6\linewidth]{../figures/fig2a_stated.pdf}
\caption{Stated, \StatedGap{} (a caption's macro is not the body's).}\label{fig:fig2a}
\includegraphics{../figures/fig2a_located.pdf}
\caption{Located.}\label{fig:fig2b}
\end{figure}
% \begin{table} a comment is no float \end{table}
\begin{table}[tbp]
\caption{Verdict.}\label{tab:verdict}
\begin{tabular}{ll} \ClaimAVerdict & \LocatedGap \\ \end{tabular}
\end{table}
\begin{figure}
\begin{tikzpicture}\end{tikzpicture}
\caption{The model.}\label{fig:model}
\end{figure}
"""


def test_floats_are_split_by_label_and_read_their_files_and_body_macros():
    fl = pv.floats(REPORT)
    assert [f.label for f in fl] == ["fig:fig2a", "fig:fig2b", "tab:verdict", "fig:model"]
    assert fl[0].files == ("figures/fig2a_stated.pdf",) and "StatedGap" not in fl[0].macros
    assert fl[1].files == ("figures/fig2a_located.pdf",)
    assert {"ClaimAVerdict", "LocatedGap"} <= set(fl[2].macros)
    homes = pv.macro_homes({"paper/generated/verdict_macros.tex": r"\newcommand{\ClaimAVerdict}{no}" + "\n"})
    rows = pv.float_rows(RULES, fl, homes)
    assert [(r.what, r.rule) for r in rows] == [
        (r"Fig.~\ref{fig:fig2a}", "fig2a"),
        (r"Fig.~\ref{fig:fig2b}", "fig2a"),
        (r"Table~\ref{tab:verdict}", "verdict"),
        (r"Fig.~\ref{fig:model}", None),
    ]
    assert rows[1].records == ("figures/fig2a_located.csv", "figures/reference_located.json")


def test_inline_sections_follows_inputs_of_sections_only():
    files = {"sections/a.tex": r"A \input{sections/b.tex}", "sections/b.tex": "B"}
    assert pv.inline_sections(r"\input{sections/a.tex} \input{generated/x.tex}", files.__getitem__) == (
        r"A B \input{generated/x.tex}"
    )


def test_inline_sections_follows_optional_inputs_where_the_file_exists():
    files = {"sections/a.tex": "A", "sections/b.tex": r"B \input{sections/a.tex}"}
    tex = r"\InputIfFileExists{sections/b}{}{} \InputIfFileExists{sections/missing}{}{}."
    assert pv.inline_sections(tex, _reader(files)) == "B A ."


def _reader(files):
    def read(name):
        if name not in files:
            raise FileNotFoundError(name)
        return files[name]

    return read


def test_the_author_line_and_locator_come_from_the_citation_metadata():
    tex = pv.citation_macros({"authors": [{"name": "The impactdamper project"}], "version": "0.1.0"})
    assert r"\newcommand{\ReportAuthors}{The impactdamper project}" in tex
    assert r"\newcommand{\ReportLocator}{the archive accompanying this report}" in tex
    tex = pv.citation_macros(
        {
            "authors": [{"given-names": "A.", "family-names": "B"}, {"given-names": "C.", "family-names": "D_E"}],
            "repository-code": "https://example.org/x",
        }
    )
    assert r"\newcommand{\ReportAuthors}{A. B and C. D\_E}" in tex
    assert r"\newcommand{\ReportLocator}{\url{https://example.org/x}}" in tex


def test_the_compact_table_gathers_each_rules_parts_and_flags_uncommitted_timings():
    rules = pv.rules_from_data(
        [
            {"name": "fig2a", "script": "workflow/scripts/fig2a.py", "outputs": ["figures/fig2a.pdf"], "inputs": []},
            {
                "name": "claims_by_parameter",
                "script": "workflow/scripts/claims_gather.py",
                "outputs": ["paper/generated/claims_table.tex"],
                "inputs": ["figures/claims.csv"],
            },
            {
                "name": "performance_report",
                "script": "workflow/scripts/performance_report.py",
                "outputs": ["paper/generated/performance_macros.tex"],
                "inputs": ["results/benchmarks/work_precision.json", "figures/compiled_speed.json"],
            },
        ]
    )
    rows = [
        pv._Row("Fig.~1", "fig2a", None, ()),
        pv._Row("Table~2", "performance_report", None, ()),
        pv._Row("Fig.~3", "fig2a", None, ()),
        pv._Row(r"\path{paper/generated/performance_macros.tex}", "performance_report", None, ()),
        pv._Row("Table~4", "claims_by_parameter", None, ()),
        pv._Row("Fig.~5", None, None, ()),
    ]
    compact = pv.compact_rows(rules, rows)
    assert [(r.rule, r.parts, r.uncommitted) for r in compact] == [
        ("fig2a", ("Fig.~1", "Fig.~3"), False),
        ("performance_report", ("Table~2", r"\path{paper/generated/performance_macros.tex}"), True),
        ("claims_by_parameter", ("Table~4",), False),
    ]
    tex = pv.compact_table(compact, "Where.", "tab:p")
    # two halves side by side: rows 1 and 3 on the first line, row 2 alone on the second;
    # the dagger on a rule reading timings; the script named where it is not the rule's own
    assert (
        r"\path{fig2a} & Fig.~1, Fig.~3 & \path{claims_by_parameter} & Table~4 (script \path{claims_gather.py}) \\"
    ) in tex
    assert r"\path{performance_report}$^\dagger$ & Table~2, \path{performance_macros.tex} & & \\" in tex
    assert tex.count(r"\label{tab:p}") == 1


def test_the_commit_is_read_from_git_and_a_changed_source_is_said(tmp_path):
    import subprocess

    def git(*args):
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)

    assert pv.source_commit(tmp_path) == {"commit": None, "dirty": False}  # not a checkout
    git("init", "-q")
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "a.py").write_text("x = 1\n")
    (tmp_path / "paper" / "generated").mkdir(parents=True)
    (tmp_path / "paper" / "generated" / "m.tex").write_text("1\n")
    git("add", ".")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "c")
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=tmp_path, capture_output=True, text=True).stdout.strip()
    assert pv.source_commit(tmp_path) == {"commit": head, "dirty": False}
    (tmp_path / "paper" / "generated" / "m.tex").write_text("2\n")  # a generated file: not a source
    assert pv.source_commit(tmp_path)["dirty"] is False
    (tmp_path / "src" / "a.py").write_text("x = 2\n")
    assert pv.source_commit(tmp_path) == {"commit": head, "dirty": True}
    tex = pv.citation_macros({"authors": [{"name": "P"}], "version": "0.1.0"}, {"commit": head, "dirty": True})
    assert rf"\newcommand{{\ReportCommit}}{{{head[:12]}}}" in tex
    assert "with changes to its sources not yet committed" in tex
    assert "commit unknown" in pv.citation_macros({"authors": [{"name": "P"}], "version": "0.1.0"})
