"""The performance stage's DAG (workflow/rules/performance.smk): a dry run with the
CI config, no job executed. Every rule lists its script, the library and a log; rule all asks
for the stage's products; the timed rules take both cores."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
from helpers import LIBRARY, library_imports, library_parts  # noqa: E402 (the library's modules, what a script imports)

RULES = (
    "performance_work_precision",
    "fig_work_precision",
    "performance_cost_growth",
    "fig_cost_growth",
    "performance_hardcases",
    "performance_reference_speed",
    "performance_compiled_map",
    "performance_compiled_speed",
    "performance_report",
)
TARGETS = (
    "figures/work_precision.pdf",
    "figures/work_precision.png",
    "figures/work_precision.csv",
    "figures/cost_growth.pdf",
    "figures/cost_growth.csv",
    "figures/hardcases.csv",
    "paper/generated/hardcases_table.tex",
    "paper/generated/performance_macros.tex",
    "paper/generated/workprecision_table.tex",
    "paper/generated/compiled_speed_table.tex",
    "results/benchmarks/reference_speed.json",
    "figures/compiled_speed.json",
)


@pytest.fixture(scope="module")
def jobs(ci_dry_run) -> dict:
    """Each rule's (fields, listing) in the session's dry run (tests/workflow/conftest.py)."""
    found = {}
    for block in re.split(r"\n(?=(?:local)?rule \w+:)", ci_dry_run):
        m = re.match(r"(?:local)?rule (\w+):", block)
        if m:
            found[m.group(1)] = (dict(re.findall(r"^\s+(input|output|log|threads): (.*)$", block, flags=re.M)), block)
    return found


def test_every_rule_is_in_the_dag(jobs):
    assert set(RULES) <= set(jobs)
    all_inputs = jobs["all"][0]["input"]
    for target in TARGETS:
        assert target in all_inputs


@pytest.mark.slow
def test_every_rule_lists_library_script_and_log(jobs):
    for rule in RULES:
        fields, _ = jobs[rule]
        inputs = [s.strip() for s in fields["input"].split(",")]
        scripts = [s for s in inputs if s.startswith("workflow/scripts/")]
        assert scripts, rule
        needed = set(library_imports(ROOT / scripts[0]))
        assert needed and needed <= set(inputs), (rule, sorted(needed - set(inputs)))
        # Whole parts, and only the ones it imports (a figure does not rerun for a new baseline).
        assert library_parts(set(inputs) & set(LIBRARY)) == library_parts(needed), rule
        assert fields["log"].startswith("logs/performance/"), rule


def test_timed_rules_take_one_core_but_the_map_benchmark_both_and_one_blas_thread(jobs):
    """The timed rules share the machine (CPU time, with the load recorded); the compiled
    benchmark's map is timed in wall time on two processes, so that rule (and only it) takes
    both cores, first of all."""
    for rule in (
        "performance_work_precision",
        "performance_cost_growth",
        "performance_hardcases",
        "performance_reference_speed",
        "performance_compiled_speed",
    ):
        fields, block = jobs[rule]
        assert fields.get("threads") is None, rule
    assert jobs["performance_compiled_map"][0].get("threads") == "2"
    assert "results/benchmarks/compiled_map.json" in jobs["performance_compiled_speed"][0]["input"]
    # One BLAS thread in each: every script starts its stage through start_stage (run_stage calls
    # it), which sets it (tests/unit/test_blas.py).
    for script in ("work_precision", "cost_growth", "hardcases", "reference_speed", "compiled_speed"):
        text = (ROOT / "workflow" / "scripts" / f"{script}.py").read_text()
        assert "run_stage(snakemake" in text or "start_stage(sm" in text, script


def test_figure_rules_list_the_style(jobs):
    for rule in ("fig_work_precision", "fig_cost_growth"):
        assert "src/impactdamper/reporting/paper.mplstyle" in jobs[rule][0]["input"]


# --- the compiled solver's numbers in the report -------------------------------------------------
def test_met_word_is_judged_from_number_and_target():
    from performance_report import met

    assert met(2.5, 3.0, at_most=True) == "met"
    assert met(3.5, 3.0, at_most=True) == "not met"
    assert met(390.0, 300.0, at_most=False) == "met"
    assert met(68.0, 100.0, at_most=False) == "not met"
    assert met(16.0, float("inf"), at_most=True) == "---"  # no target at this map size


def test_compiled_speed_words_agree_with_the_benchmark(tmp_path):
    """The report's words (judged from number and target) and the benchmark's own flags
    (figures/compiled_speed.json) say the same, and the table holds only macros."""
    import json

    from performance_report import compiled_speed, compiled_table

    cs = json.loads((ROOT / "figures" / "compiled_speed.json").read_text())
    c = compiled_speed(cs)
    word = {True: "met", False: "not met"}
    st = cs["steady_state"]["targets"]
    assert c["us_per_impact"]["met"] == word[cs["per_impact"]["met"]]
    assert c["steady_seconds"]["met"] == word[st["time_met"]]
    assert c["steady_speedup"]["met"] == word[st["speedup_met"]]
    assert c["steady_phase_error"]["met"] == word[st["phase_met"]]
    assert c["first_speedup"]["met"] == word[cs["first_10_impacts"]["met"]]
    first_map = cs["maps"].get("200x200") or next(iter(cs["maps"].values()))
    assert c["map_wall"]["met"] == ({True: "met", False: "not met", None: "---"}[first_map["met"]])
    body = [
        re.sub(r"\\[A-Za-z]+|DOP853", "", ln)
        for ln in compiled_table(c).splitlines()
        if "&" in ln and not ln.startswith("Measure")
    ]
    assert body and not any(ch.isdigit() for ln in body for ch in ln), body  # numbers only through macros


# --- the compile time: measured once at set-up -----------------------------------------------------
def test_compile_time_is_read_from_the_setup_record_while_it_is_current(tmp_path):
    """tools/setup.sh measures it (the record's ``measured``: set-up); the workflow reads that
    record while the kernels' sources and numba are the same, and measures it in the run
    otherwise (rule performance_compile_time)."""
    import json

    from impactdamper.studies.performance import compile_record as cr

    setup = (ROOT / "tools" / "setup.sh").read_text()
    assert "write_compile_record" in setup and "results/setup/compile_time.json" in setup
    path = tmp_path / "compile_time.json"
    assert not cr.current_compile_record(path)  # missing
    record = {"compile": {"cold_compile_s": 60.0, "cached_load_s": 1.0}, "measured": cr.MEASURED_AT_SETUP}
    path.write_text(json.dumps({**record, "sources": cr._sources_fingerprint()}))
    assert cr.current_compile_record(path)
    path.write_text(json.dumps({**record, "sources": "another kernel"}))
    assert not cr.current_compile_record(path)  # stale: measured again in the run
    path.write_text("{")
    assert not cr.current_compile_record(path)
    text = (ROOT / "workflow" / "rules" / "performance.smk").read_text()
    assert "current_compile_record(SETUP_COMPILE_RECORD)" in text and "compile_time=COMPILE_TIME" in text
