"""The README's numbers come from the workflow: its generated block is a verbatim copy of
figures/readme_summary.md (written by workflow/scripts/readme_summary.py), a short table of the
results whose verdicts and numbers are those of the committed records and whose sections are
the report's; and the two commands it documents are the ones CI and users run."""

import json
import re
from pathlib import Path

from helpers import parse_results_table
from readme_summary import SYMBOLS  # the README's names of the parameters

ROOT = Path(__file__).resolve().parents[2]
BEGIN = "<!-- BEGIN generated: figures/readme_summary.md -->"
END = "<!-- END generated -->"


def test_readme_results_block_is_the_generated_summary():
    readme = (ROOT / "README.md").read_text()
    assert readme.count(BEGIN) == 1 and readme.count(END) == 1
    block = readme.split(BEGIN)[1].split(END)[0].strip("\n") + "\n"
    assert block == (ROOT / "figures" / "readme_summary.md").read_text()


def test_ci_runs_the_readme_test_command():
    readme = (ROOT / "README.md").read_text()
    commands = re.findall(r"^\s*(\.venv/bin/python -m pytest[^#\n]*)", readme, flags=re.M)
    assert commands, "the README must show its test command"
    ci = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()]
    assert commands[0].strip() in ci


# --- The results table says what the committed records say ---------------------------------------
def _table() -> dict[str, dict[str, str]]:
    """The README block's results table, rows by the start of their first cell."""
    readme = (ROOT / "README.md").read_text()
    rows = parse_results_table(readme.split(BEGIN)[1].split(END)[0])
    return {r["claim or question"]: r for r in rows}


def _row(table: dict, start: str) -> dict[str, str]:
    found = [r for claim, r in table.items() if claim.startswith(start)]
    assert len(found) == 1, (start, list(table))
    return found[0]


def _json(name: str) -> dict:
    return json.loads((ROOT / "figures" / name).read_text())


def test_the_results_table_is_short_and_names_sections_of_the_report():
    table = _table()
    assert 6 <= len(table) <= 14
    titles = set()
    for path in (ROOT / "paper" / "sections").glob("*.tex"):
        titles |= set(re.findall(r"\\section\{([^}]*)\}", path.read_text().replace("~", " ")))
    for row in table.values():
        for section in row["in the report"].split("; "):
            assert section in titles, (section, sorted(titles))


def test_the_verdicts_are_the_verdict_records():
    table, claims = _table(), {c["claim"]: c for c in _json("verdict.json")["claims"]}
    words = {True: "**reproduced**", False: "**not reproduced**"}
    assert _row(table, "The paper's Fig. 2a")["verdict or answer"] == words[claims["a"]["reproduced"]]
    assert (
        _row(table, "The paper's Fig. 2b at the stated case (Δ0/x_st = -5.8): T_c = 2T")["verdict or answer"]
        == (words[claims["b_period"]["reproduced"]])
    )
    assert (
        _row(table, "The paper's Fig. 2b at the stated case (Δ0/x_st = -5.8): three")["verdict or answer"]
        == (words[claims["b_impacts"]["reproduced"]])
    )


def test_the_ranges_and_distances_are_the_searches_records():
    table = _table()
    both = _json("located_case.json")["both_ranges"][0]
    assert (
        _row(table, "Where both claims hold")["verdict or answer"] == f"Δ0/x_st in [{both['lo']:.3f}, {both['hi']:.3f}]"
    )
    search = _json("claims_by_parameter_settings.json")["parameters"]
    near = min(
        (n for n in search if search[n]["nearest_both"]["relative_distance"] is not None),
        key=lambda n: search[n]["nearest_both"]["relative_distance"],
    )
    d = search[near]
    iv = next(r for r in d["intervals"]["both"] if r["lo"] <= d["nearest_both"]["nearest"] <= r["hi"])
    stated = d["nearest_both"]["stated"]
    far = max(abs(iv["lo"] - stated), abs(iv["hi"] - stated)) / abs(stated)
    answer = _row(table, "The nearest change of one parameter alone")["verdict or answer"]
    assert answer.startswith(f"{SYMBOLS[near]} in [{iv['lo']:.4f}, {iv['hi']:.4f}]"), answer
    assert f"{100 * d['nearest_both']['relative_distance']:.1f} to {100 * far:.1f} %" in answer, answer
    evidence = _row(table, "The nearest change of one parameter alone")["evidence"]
    dependent = d["nearest_both"]["nearest"] in d.get("solver_dependent_ends", [])
    assert ("depends on the solver" in evidence) == dependent
    joint = _json("claims_nearest.json")["joint"]["answers"]["max"]["distance"]["max"]
    assert f"more than {100 * joint:.1f} %" in _row(table, "The nearest set of all seven")["verdict or answer"]
    readings = _json("other_readings.json")["readings"]
    reproducing = sum(bool(r["reproduces"]) for r in readings if r["id"] != "stated")
    assert _row(table, "Another reading")["verdict or answer"].startswith(f"{reproducing} of {len(readings) - 1} ")


def test_the_closed_form_checks_and_the_design_are_their_records():
    table = _table()
    doc = _json("sweep_checks.json")
    within = sum(abs(c["analytic_minus_located"]) <= float(doc["check_xtol"]) for c in doc["checks"])
    assert _row(table, "Three transitions")["verdict or answer"].startswith(f"{within} of {len(doc['checks'])} within")
    devices = {d["device"]: d for d in _json("design_optimum.json")["devices"]}
    evidence = _row(table, "Impact suppressor or tuned-mass damper")["evidence"]
    assert f"the TMD {devices['tmd_peak']['peak']:.3f}" in evidence
    assert f"in reach {devices['impact_peak_reach']['peak']:.3f}" in evidence
    assert f"bare object {devices['bare object']['peak']:.3f}" in evidence


# --- How long the commands take: the timed run's record (tools/time_commands.py) -----------------
def _duration(seconds: float) -> str:
    s = int(round(seconds))
    return f"{s // 60} min {s % 60} s" if s >= 60 else f"{s} s"


def test_the_readme_says_how_long_the_commands_took_in_the_timed_run():
    """The README's times are those of figures/command_times.json, and the commands timed there
    are the ones the README shows."""
    times = _json("command_times.json")["commands"]
    readme = (ROOT / "README.md").read_text()
    said = " ".join(readme.split("How long they take")[1].split("\n\n")[0].split())
    for name in ("setup", "workflow", "coarse", "quick_tests"):
        assert times[name]["command"] in readme.replace("  ", " ") and times[name]["exit_code"] == 0, name
        assert f"{times[name]['what']} {_duration(times[name]['wall_s'])}" in said, (name, said)
    assert f"{_duration(times['workflow']['cpu_s'])} of processor time" in said, said
