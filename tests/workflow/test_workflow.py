"""The Snakemake workflow: lint, the config schema, and the reference-case stage's DAG.

Every test here is a dry run (``snakemake -n``) or a lint: no job is executed. A bad config
value must stop the run with a message naming the key (the schema in
workflow/schemas/config.schema.yaml); the tests write a small override file, which Snakemake
merges over config/config.yaml.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
SNAKEMAKE = [sys.executable, "-m", "snakemake"]
from helpers import LIBRARY, library_imports, library_parts, shipped_config  # noqa: E402 (the library's modules, what a script imports)

REFERENCE_RULES = (
    "reference_case_stated",
    "reference_case_located",
    "gap_scan",
    "fig2a",
    "fig2b",
    "impact_table",
    "crosscheck_case",
    "other_readings",
    "fig_located_range",
    "verdict",
)
REFERENCE_TARGETS = (
    [f"figures/fig2{panel}_{case}.{ext}" for panel in "ab" for case in ("stated", "located") for ext in ("pdf", "png")]
    + [f"figures/impacts_{case}.csv" for case in ("stated", "located")]
    + [f"paper/generated/impacts_{case}.tex" for case in ("stated", "located")]
    + ["figures/located_range.pdf", "figures/located_range.png"]
    + ["figures/verdict.json", "figures/verdict.csv", "paper/generated/verdict_macros.tex"]
)


def snakemake(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([*SNAKEMAKE, "--nolock", *args], cwd=ROOT, capture_output=True, text=True, timeout=300)


def dry_run_with(tmp_path: Path, override: str, *targets: str) -> subprocess.CompletedProcess:
    cfg = tmp_path / "override.yaml"
    cfg.write_text(override)
    return snakemake("-n", *targets, "--configfile", str(cfg))  # --configfile takes several values: last


# --- lint -------------------------------------------------------------------------------------
@pytest.mark.slow
def test_lint_is_clean():
    out = snakemake("--lint")
    assert out.returncode == 0, out.stdout + out.stderr
    assert "Congratulations, your workflow is in a good condition" in out.stdout + out.stderr


# --- the schema rejects bad values, naming the key --------------------------------------------
def _config_with(override: dict) -> dict:
    """config/config.yaml with a section's keys overridden (as Snakemake merges --configfile)."""
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    for section, values in override.items():
        config.setdefault(section, {}).update(values)
    return config


@pytest.mark.parametrize(
    ("override", "key", "why"),
    [
        ({"reference": {"R": 1.5}}, "['reference']['R']", "greater than the maximum of 1"),
        ({"reference": {"gap": "minus five"}}, "['reference']['gap']", "is not of type 'number'"),
        ({"reference": {"theta": 0}}, "['reference']['theta']", "less than or equal to the minimum of 0"),
        ({"solver": {"max_periods": 1.5}}, "['solver']['max_periods']", "is not of type 'integer'"),
        ({"verdict": {"gap_step": -0.1}}, "['verdict']['gap_step']", "less than or equal to the minimum of 0"),
        ({"verdict": {"ivp_method": "Euler"}}, "['verdict']['ivp_method']", "is not one of"),
        ({"verdict": {"random_states": "many"}}, "['verdict']['random_states']", "is not of type 'integer'"),
        ({"verdict": {"gap_stepp": 0.1}}, "['verdict']", "('gap_stepp' was unexpected)"),
    ],
)
def test_schema_rejects_bad_value_naming_the_key(override, key, why):
    """The same validation the Snakefile runs (snakemake.utils.validate), in process."""
    from snakemake.exceptions import WorkflowError
    from snakemake.utils import validate

    with pytest.raises(WorkflowError) as err:
        validate(_config_with(override), str(SCHEMA))
    text = str(err.value)
    assert key in text and why in text, text


@pytest.mark.parametrize(
    ("value", "why"),
    [(7, "greater than the maximum of 6"), (-1, "less than the minimum of 0"), (1.5, "is not of type 'integer'")],
)
def test_schema_rejects_bad_map_refine_levels(value, why):
    """claims_search.map.refine_levels (and each pair map's): an integer in [0, 6]."""
    from snakemake.exceptions import WorkflowError
    from snakemake.utils import validate

    search = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["claims_search"]
    for where in ("map", "pair_maps"):
        changed = dict(search)
        if where == "map":
            changed["map"] = dict(search["map"], refine_levels=value)
        else:
            changed["pair_maps"] = dict(
                search["pair_maps"], theta_N=dict(search["pair_maps"]["theta_N"], refine_levels=value)
            )
        with pytest.raises(WorkflowError) as err:
            validate(_config_with({"claims_search": changed}), str(SCHEMA))
        text = str(err.value)
        assert "refine_levels" in text and why in text, text


@pytest.mark.parametrize("name", ["config.yaml", "ci.yaml"])
def test_shipped_configs_are_valid(name):
    from snakemake.utils import validate

    validate(shipped_config(name), str(SCHEMA))  # ci.yaml merged over config.yaml, as a run reads it


@pytest.mark.slow
def test_snakemake_stops_on_bad_value_naming_the_key(tmp_path):
    """End to end: a user's override file with an out-of-range value stops the dry run."""
    out = dry_run_with(tmp_path, "reference:\n  R: 1.5\n", "reference")
    text = out.stdout + out.stderr
    assert out.returncode != 0
    assert "Error validating config file" in text
    assert "['reference']['R']" in text and "1.5 is greater than the maximum of 1" in text


# --- the stage's DAG ---------------------------------------------------------------------------
@pytest.fixture(scope="module")
def forced_dry_run(ci_dry_run) -> str:
    """The whole DAG (rule all), every job forced, with the CI config (also shows it is valid
    end to end): the session's one dry run (tests/workflow/conftest.py)."""
    return ci_dry_run


def _jobs(text: str) -> list[tuple[str, dict]]:
    """(rule, fields) of every job in a dry run's listing."""
    jobs = []
    for block in re.split(r"\n(?=(?:local)?rule \w+:)", text):
        m = re.match(r"(?:local)?rule (\w+):", block)
        if not m:
            continue
        fields = dict(re.findall(r"^\s+(input|output|log|wildcards): (.*)$", block, flags=re.M))
        jobs.append((m.group(1), fields))
    return jobs


def test_stage_has_every_rule_and_target(forced_dry_run):
    jobs = _jobs(forced_dry_run)
    rules = {rule for rule, _ in jobs}
    assert set(REFERENCE_RULES) <= rules
    outputs = ", ".join(f.get("output", "") for _, f in jobs)
    for target in REFERENCE_TARGETS:
        assert target in outputs


def test_all_includes_the_stage(forced_dry_run):
    all_job = [f for rule, f in _jobs(forced_dry_run) if rule == "all"]
    assert all_job and all(t in all_job[0]["input"] for t in REFERENCE_TARGETS)


def test_every_job_lists_library_and_script_and_log(forced_dry_run):
    """A change to the library's source must rerun the stage: every job lists its script and
    the library files the script imports (followed through the library), and writes a log."""
    for rule, fields in _jobs(forced_dry_run):
        if rule not in REFERENCE_RULES:
            continue
        inputs = [s.strip() for s in fields["input"].split(",")]
        scripts = [s for s in inputs if s.startswith("workflow/scripts/")]
        assert scripts, rule
        assert fields.get("log", "").startswith("logs/reference/"), rule


@pytest.mark.slow
def test_every_job_lists_the_library_parts_it_imports_and_no_other(forced_dry_run):
    """Every job that runs a script or notebook lists the library files it imports (followed
    through the library's own imports) and, of the library, whole parts it imports only: a
    change to a study reruns its stage, not the figures of another (workflow/rules/common.smk)."""
    checked = set()
    for rule, fields in _jobs(forced_dry_run):
        inputs = [s.strip() for s in fields.get("input", "").split(",")]
        scripts = [s for s in inputs if s.startswith(("workflow/scripts/", "notebooks/"))]
        if not scripts:
            continue
        needed = set().union(*(library_imports(ROOT / s) for s in scripts))
        if any('"-m", "impactdamper"' in (ROOT / s).read_text() for s in scripts):
            # A script that runs the command as a user does (a fresh process, the design
            # benchmark) depends on what the command imports.
            needed |= set(library_imports(ROOT / "src" / "impactdamper" / "cli" / "commands.py")) & set(LIBRARY)
        listed = set(inputs) & set(LIBRARY)
        assert needed <= listed, (rule, sorted(needed - listed))
        assert library_parts(listed) == library_parts(needed), (rule, library_parts(listed) - library_parts(needed))
        checked.add(rule)
    # Every stage's scripts were seen (the dry run covers the whole DAG).
    assert {
        "verdict",
        "sweep_transitions",
        "orbit_report",
        "performance_hardcases",
        "readme_summary",
        "notebook_gap_sweep",
        "fig_regime_map",
    } <= checked


@pytest.mark.slow
def test_every_job_running_compiled_code_waits_for_the_warm_up(forced_dry_run):
    """Jobs whose script imports the compiled kernels (core/compiled, numba) take the warm-up's
    output as an input, so that parallel jobs load numba's cache instead of each compiling for
    tens of seconds (rule compiled_warm_up, workflow/rules/common.smk)."""
    warm_up = "results/compiled/warm_up.json"
    users = set()
    for rule, fields in _jobs(forced_dry_run):
        inputs = [s.strip() for s in fields.get("input", "").split(",")]
        scripts = [s for s in inputs if s.startswith(("workflow/scripts/", "notebooks/"))]
        needed = set().union(*(library_imports(ROOT / s) for s in scripts)) if scripts else set()
        if rule == "compiled_warm_up" or not any(f.startswith("src/impactdamper/core/compiled/") for f in needed):
            continue
        assert warm_up in inputs, rule
        users.add(rule)
    assert {"map_chunk", "performance_compiled_speed", "claims_parameter", "design_chart"} <= users


def test_a_jobs_worker_processes_are_its_threads(forced_dry_run):
    """No script starts more worker processes than its job's threads (Snakemake counts a job's
    cores by them): scripts take their workers from the job (``workers=threads``), never from
    the library's default, and the design table and the design command's benchmark, which run
    the design command's two workers, hold two cores (declared as one, each ran a third process
    beside another job and measured its time on a shared core)."""
    from impactdamper.studies.design.optimum import WORKERS

    for script in (ROOT / "workflow" / "scripts").glob("*.py"):
        assert not re.search(r"\bWORKERS\b", script.read_text()), script.name
    threads = {}
    for block in re.split(r"\n(?=(?:local)?rule \w+:)", forced_dry_run):
        m = re.match(r"(?:local)?rule (\w+):", block)
        if m:
            found = re.search(r"^\s+threads: (\d+)$", block, flags=re.M)
            threads[m.group(1)] = int(found.group(1)) if found else 1
    assert threads["design_optimum"] == threads["design_benchmark"] == WORKERS == 2
    assert "workers=threads" in (ROOT / "workflow" / "scripts" / "design_optimum.py").read_text()
    assert {rule for rule, n in threads.items() if n > 1} == {
        "performance_compiled_map",
        "design_optimum",
        "design_benchmark",
    }


def test_figure_jobs_list_the_style(forced_dry_run):
    for rule, fields in _jobs(forced_dry_run):
        if rule in ("fig2a", "fig2b", "fig_located_range"):
            assert "src/impactdamper/reporting/paper.mplstyle" in fields["input"]
            assert "src/impactdamper/reporting/plotting.py" in fields["input"]


# --- a config error the schema cannot express -------------------------------------------------
def test_scan_window_must_be_ordered(tmp_path):
    import gap_scan

    verdict = {"gap_min": -9.0, "gap_max": -10.0}
    with pytest.raises(ValueError, match=r"`verdict.gap_min` = -9.0 is not allowed: must be < `verdict.gap_max`"):
        gap_scan.main({}, {}, verdict, tmp_path / "scan.csv", tmp_path / "scan.json")


# --- the README's --config example ------------------------------------------------------------
@pytest.mark.slow
def test_config_override_on_the_command_line_is_typed():
    """Regression: Snakemake hands a nested --config dict's values over as strings, and the
    schema rejected the README's own example ("'1.1' is not of type 'number'")."""
    case = (
        "{theta: 1.1, mu: 0.08, N: 0.5, delta1: 0.05, delta2: 0.05, R: 0.7, gap: -7.0, omega: 10.0, x_st: 1.0, m1: 1.0}"
    )
    ok = snakemake("-n", "--config", f"reference={case}")
    assert ok.returncode == 0, ok.stdout + ok.stderr
    bad = snakemake("-n", "--config", "reference=" + case.replace("theta: 1.1", "theta: -1"))
    assert bad.returncode != 0
    assert "theta" in bad.stdout + bad.stderr


# --- config errors: unknown keys, NaN and inf, reversed ranges, numbers in any YAML form -------------
# (the checks themselves, in process: tests/unit/test_config_check.py; here, end to end)
@pytest.mark.slow
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--config", "refrence={theta: 5}"), "['refrence'] is not a config key: did you mean 'reference'?"),
        (("--config", "reference={gap: .nan}"), "['reference']['gap']: nan is not allowed: must be a finite number"),
        (("--config", "sweep={start: 14, stop: -34}"), "['sweep']: start = 14 is not allowed: must be < stop = -34"),
        (
            ("--config", "design={theta_start: 2.0}"),
            "['design']: theta_start = 2.0 is not allowed: must be < theta_stop = 1.5",
        ),
    ],
)
def test_snakemake_stops_on_a_typo_nan_or_reversed_range_in_a_short_message(args, message):
    out = snakemake("-n", *args)
    text = out.stdout + out.stderr
    assert out.returncode != 0 and message in text, text
    assert len(text.splitlines()) < 10, text  # the message and Snakemake's frame lines, not a schema dump


@pytest.mark.slow
def test_snakemake_reads_numbers_in_any_yaml_form(tmp_path):
    """1e-12 without a dot (YAML 1.1 reads it as a string) in a config file and in --config, and
    a quoted 'yes' where a string is expected, are accepted (were "not of type 'number'"/True)."""
    override = (
        "solver:\n  gap_tol: 1e-12\n  chatter_tol: 1e-9\n  max_periods: 4e3\n"
        "orbits:\n  cases:\n    - {name: 'yes', gap: -1e1}\n"
    )
    out = dry_run_with(tmp_path, override, "reference")
    assert out.returncode == 0, out.stdout + out.stderr
    ok = snakemake("-n", "reference", "--config", "verdict={ivp_atol: 1e-10, ivp_rtol: 1e-10}")
    assert ok.returncode == 0, ok.stdout + ok.stderr


# --- values read as written, limits refused at validation -----------------------------------
# Each case is a snakemake dry run (~4 s): the config checker's own tests (tests/unit/
# test_config_check.py) hold every case in the library; here end to end, two in the quick tier
# (a YAML 1.1 form and a limit the job would refuse), the others in the slow one.
SLOW = pytest.mark.slow
END_TO_END_REFUSALS = [
    # YAML 1.1 forms that --config's values were read in (gap 8, theta 90, gap 16, rescue True)
    ("reference={gap: 010}", "['reference']['gap']: 010 is not allowed: YAML 1.1 reads it as 8"),
    pytest.param(
        "reference={theta: 1:30}", "['reference']['theta']: 1:30 is not allowed: YAML 1.1 reads it as 90", marks=SLOW
    ),
    pytest.param(
        "reference={gap: 0x10}", "['reference']['gap']: 0x10 is not allowed: YAML 1.1 reads it as 16", marks=SLOW
    ),
    pytest.param("maps={rescue: on}", "['maps']['rescue']: on is not allowed: YAML 1.1 reads it as True", marks=SLOW),
    # documented limits that passed validation and failed only in the job
    ("reference={mu: 1e-320}", "['reference']: `mu` = 1e-320 is not allowed with the other parameters"),
    pytest.param(
        "design={second: R, second_values: [0.5, 1.2]}",
        "['design']['second_values']: `R` = 1.2 is not allowed",
        marks=SLOW,
    ),
    pytest.param(
        "claims_search={parameters: {R: {start: 0.5, stop: 1.5, points: 3, alg1_points: 3}}}",
        "['claims_search']['parameters']['R']['stop']: `R` = 1.5 is not allowed",
        marks=SLOW,
    ),
    pytest.param(
        "claims_search={parameters: {theta: {start: 0, stop: 2, points: 3, alg1_points: 3}}}",
        "['claims_search']['parameters']['theta']['start']: `theta` = 0.0 is not allowed: must be > 0",
        marks=SLOW,
    ),
    pytest.param(
        "claims_search={map: {x: R, x_stop: 1.2}}",
        "['claims_search']['map']['x_stop']: `R` = 1.2 is not allowed",
        marks=SLOW,
    ),
    # chunk counts: bounded, and never above the rows they split (a dry run spun on 100000)
    pytest.param("maps={chunks: 100000}", "['maps']['chunks']: 100000 is greater than the maximum of 1000", marks=SLOW),
    pytest.param("maps={chunks: 500}", "['maps']['chunks']: 500 is not allowed: must be at most 400", marks=SLOW),
    pytest.param(
        "claims_search={map: {coarse_step: 100}}",
        "['claims_search']['map']['coarse_step']: 100 is greater than the maximum of 64",
        marks=SLOW,
    ),
]


@pytest.mark.parametrize(("config", "message"), END_TO_END_REFUSALS)
def test_snakemake_stops_on_a_yaml11_number_or_a_limit_the_job_would_refuse(config, message):
    out = snakemake("-n", "reference", "--config", config)
    text = out.stdout + out.stderr
    assert out.returncode != 0 and message in text, text
    line = next(x for x in text.splitlines() if message in x)
    assert line.startswith("Error validating config file") and len(text.splitlines()) < 10, text


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("reference:\n  gap: -5.0\n  gap: -6.0\n", "['reference']['gap'] is given twice"),
        pytest.param(
            "reference:\n  gap: 010\n", "['reference']['gap']: 010 is not allowed: YAML 1.1 reads it as 8", marks=SLOW
        ),
        pytest.param(
            "maps:\n  rescue: yes\n", "['maps']['rescue']: yes is not allowed: YAML 1.1 reads it as True", marks=SLOW
        ),
    ],
)
def test_snakemake_stops_on_a_repeated_key_or_yaml11_value_in_a_config_file(tmp_path, override, message):
    out = dry_run_with(tmp_path, override, "reference")
    text = out.stdout + out.stderr
    assert out.returncode != 0 and message in text, text
    assert f"Error validating config file {tmp_path / 'override.yaml'}: " in text


def test_decimal_numbers_and_yaml12_booleans_are_accepted(tmp_path):
    """The forms that are read as written still pass: 0.5, -0.0, 1_000, 1e-12, true."""
    override = "reference:\n  gap: -0.0\nsolver:\n  gap_tol: 1e-12\n  max_periods: 1_000\nmaps:\n  rescue: true\n"
    out = dry_run_with(tmp_path, override, "reference")
    assert out.returncode == 0, out.stdout + out.stderr


def test_config_problem_finds_nothing_in_the_shipped_configs():
    from impactdamper.studies import config_check
    from impactdamper.studies.config import config_problem

    schema = config_check.read_schema(SCHEMA)
    for name in ("config.yaml", "ci.yaml"):
        assert config_problem(config_check.typed(shipped_config(name), schema)) is None


# --- issue 33: limits at validation, end to end (a dry run stops in seconds, naming the key) --------
@pytest.mark.slow
@pytest.mark.parametrize(
    ("override", "message"),
    [
        (
            "design: {band_step: 0.4}",
            "['design']['band_step']: 0.4 is not allowed: the theta grid from 0.5 to 1.5 must contain the reference "
            "theta = 1 (such as 0.05, 0.025, 0.02)",
        ),
        ("sweep: {points: 1000000000}", "['sweep']['points']: 1000000000 is not allowed: 1000000000 sweep values"),
        (
            "maps: {theta: {points: 100000, gap_points: 100000}}",
            "['maps']['theta']: points x gap_points = 100000 x 100000 is not allowed: 10000000000 map cells; at most",
        ),
        ("verdict: {gap_step: 1.0e-9}", "['verdict']['gap_step']: 1e-09 is not allowed: 16000000000 Algorithm No. 2"),
        (
            "claims_search: {map: {x: gap, x_start: -12.0, x_stop: -4.0}}",
            "['claims_search']['map']['y']: 'gap' is not allowed: must differ from x = 'gap'",
        ),
        ("output_root: ../elsewhere", "['output_root']: '../elsewhere' is not allowed: must be '.' or a relative path"),
    ],
)
def test_snakemake_stops_on_a_config_limit_in_one_line(tmp_path, override, message):
    out = dry_run_with(tmp_path, override + "\n")
    text = out.stdout + out.stderr
    assert out.returncode != 0 and message in text, text
    line = next(x for x in text.splitlines() if message in x)
    assert line.startswith("Error validating config file: ") and len(text.splitlines()) < 10, text
    assert not (ROOT.parent / "elsewhere").exists()


# --- one convention for every rule script --------------------------------------------------------
def _rules() -> dict[str, str]:
    """Each rule's text in workflow/rules/*.smk, by name."""
    rules = {}
    for path in sorted((ROOT / "workflow" / "rules").glob("*.smk")):
        for block in re.split(r"\n(?=rule \w+:)", path.read_text()):
            m = re.match(r"rule (\w+):", block)
            if m:
                rules[m.group(1)] = block
    return rules


def test_every_rule_script_runs_through_script_with_its_settings_from_the_rule():
    """A rule that runs a workflow script runs it through ``script:`` (settings from
    snakemake.params), never from ``shell:`` with a command line; every rule script lives in
    workflow/scripts and reads no config file itself nor changes a library module's globals."""
    import ast

    rules = _rules()
    scripted = {name for name, text in rules.items() if "workflow/scripts/" in text}
    assert len(scripted) > 50 and {"performance_reference_speed", "performance_compiled_speed"} <= scripted
    for name in scripted:
        assert re.search(r"^    script:$", rules[name], flags=re.M) and "shell:" not in rules[name], name
    assert all("python " not in text for text in rules.values() if "shell:" in text)
    assert not (ROOT / "benchmarks").exists()
    for path in sorted((ROOT / "workflow" / "scripts").glob("*.py")):
        text = path.read_text()
        assert "argparse" not in text and "config.yaml" not in text, path.name
        tree = ast.parse(text)
        imported = {
            alias.asname or alias.name
            for node in ast.walk(tree)
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("impactdamper")
            for alias in node.names
        }
        for node in ast.walk(tree):
            targets = node.targets if isinstance(node, ast.Assign) else []
            for target in targets:  # impactdamper_module.NAME = ..., or IMPORTED[...] = ...
                base = target.value if isinstance(target, (ast.Attribute, ast.Subscript)) else None
                assert not (isinstance(base, ast.Name) and base.id in imported), (path.name, ast.unparse(target))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
                base = node.func.value  # IMPORTED_TABLE.update(...)
                mutating = node.func.attr in ("update", "clear", "pop", "setdefault", "append", "extend")
                assert not (mutating and isinstance(base, ast.Name) and base.id in imported and base.id.isupper()), (
                    path.name,
                    ast.unparse(node),
                )
