"""The workflow's config checker (impactdamper.studies.config_check), in process: the shipped
configs pass; every value the workflow cannot use stops with one line naming the key and what
is allowed (the Snakefile's validation, workflow/rules/common.smk, runs exactly this; the dry
runs that show it end to end are in tests/workflow/test_workflow.py)."""

import math
from pathlib import Path

import pytest
import yaml

from helpers import shipped_config
from impactdamper.studies import config_check as cc

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = cc.read_schema(ROOT / "workflow" / "schemas" / "config.schema.yaml")


def _shipped(name: str = "config.yaml") -> dict:
    return cc.typed(shipped_config(name), SCHEMA)


def _set(config: dict, path: tuple, value) -> dict:
    node = config
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return config


def _refused(config: dict) -> str:
    """The one-line message that check() stops ``config`` with."""
    with pytest.raises(cc.ConfigError) as err:
        cc.check(config, SCHEMA)
    text = str(err.value)
    assert text.startswith("Error validating config file: ") and "\n" not in text and len(text) < 300, text
    return text


@pytest.mark.parametrize("name", ["config.yaml", "ci.yaml"])
def test_the_shipped_configs_pass_and_every_grid_is_within_its_bound(name):
    config = _shipped(name)
    assert cc.check(config, SCHEMA) == config
    grids = cc.grid_sizes(cc._with_defaults(config, SCHEMA))
    assert len(grids) > 60
    assert all(0 < count <= limit for _, _, count, limit, _ in grids), [g for g in grids if g[2] > g[3]]


# --- the checks moved from workflow/rules/common.smk: the same messages ------------------------
@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        (("refrence",), {"theta": 5}, "['refrence'] is not a config key: did you mean 'reference'?"),
        (("verdict", "gap_stepp"), 0.1, "['verdict']['gap_stepp'] is not a config key: did you mean 'gap_step'?"),
        (
            ("maps", "theta", "gap_strat"),
            1.0,
            "['maps']['theta']['gap_strat'] is not a config key: did you mean 'gap_start'?",
        ),
        (
            ("orbits", "branches", 0, "gap_mx"),
            1.0,
            "['orbits']['branches'][0]['gap_mx'] is not a config key: did you mean 'gap_max'?",
        ),
        (("zzz",), 1, "['zzz'] is not a config key: allowed are reference, solver"),
        (("reference", "gap"), math.nan, "['reference']['gap']: nan is not allowed: must be a finite number"),
        (("reference", "theta"), math.inf, "['reference']['theta']: inf is not allowed: must be a finite number"),
        (("performance", "growth_gaps"), [-5.8, -math.inf], "['performance']['growth_gaps'][1]: -inf is not allowed"),
        (("reference", "R"), 1.5, "['reference']['R']: 1.5 is greater than the maximum of 1"),
        (("solver", "max_periods"), "many", "['solver']['max_periods']: 'many' is not of type 'integer'"),
        (("verdict", "gap_min"), 50.0, "['verdict']: gap_min = 50.0 is not allowed: must be < gap_max = "),
        (("sweep", "start"), 20.0, "['sweep']: start = 20.0 is not allowed: must be < stop = 14.0"),
        (
            ("maps", "damping", "gap_start"),
            40.0,
            "['maps']['damping']: gap_start = 40.0 is not allowed: must be < gap_stop",
        ),
        (
            ("orbits", "continuation", "min_step"),
            1.0,
            "['orbits']['continuation']: min_step = 1.0 is not allowed: must be <= step",
        ),
        (
            ("orbits", "branches", 0, "gap"),
            50.0,
            "['orbits']['branches'][0]: gap = 50.0 is not allowed: must be <= gap_max",
        ),
        (
            ("sweep", "max_periods_after_nonperiodic"),
            10**6,
            "['sweep']: max_periods_after_nonperiodic = 1000000 is not allowed",
        ),
        # what a job's library call would refuse (impactdamper.studies.config.config_problem)
        (("reference", "mu"), 1e-320, "['reference']: `mu` = 1e-320 is not allowed with the other parameters"),
        (("maps", "chunks"), 500, "['maps']['chunks']: 500 is not allowed: must be at most 400"),
    ],
)
def test_a_bad_value_is_named_in_one_short_line(path, value, message):
    text = _refused(_set(_shipped(), path, value))
    assert message in text, text


@pytest.mark.parametrize(
    ("text", "path", "value"),
    [
        ("1e-12", ("solver", "gap_tol"), 1e-12),
        ("1E12", ("verdict", "ivp_atol"), 1e12),
        ("-1e-9", ("reference", "gap"), -1e-9),
        ("4e3", ("solver", "max_periods"), 4000),
        ("1_000", ("solver", "max_periods"), 1000),
        ("'yes'", ("orbits", "cases", 0, "name"), "yes"),
        ("yes", ("orbits", "cases", 0, "name"), "yes"),
        (".5", ("reference", "R"), 0.5),
        ("true", ("verdict", "ivp_method"), "true"),
        ("true", ("maps", "rescue"), True),
    ],
)
def test_numbers_in_any_yaml_form_and_strings_stay_strings(text, path, value):
    """A value as the YAML file or Snakemake's --config hands it over (a string for a float
    without a dot, and for every nested --config value) is read as the schema's type."""
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    raw = yaml.safe_load(f"v: {text}")["v"]
    node = cc.typed(_set(config, path, raw if not isinstance(raw, bool) else text), SCHEMA)
    for key in path:
        node = node[key]
    assert node == value and type(node) is type(value)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("010", "['reference']['gap']: 010 is not allowed: YAML 1.1 reads it as 8"),
        ("0x10", "['reference']['gap']: 0x10 is not allowed: YAML 1.1 reads it as 16"),
        ("1:30", "['reference']['gap']: 1:30 is not allowed: YAML 1.1 reads it as 90"),
        (".nan", "['reference']['gap']: nan is not allowed: must be a finite number"),
    ],
)
def test_a_command_line_value_yaml_reads_otherwise_is_named(value, message):
    """--config values arrive as strings: one that only YAML 1.1 reads as a number is refused."""
    assert message in _refused(_set(_shipped(), ("reference", "gap"), value))


@pytest.mark.parametrize(
    ("text", "where", "why"),
    [
        ("reference:\n  gap: -5.0\n  gap: -6.0\n", "['reference']['gap']", " is given twice"),
        ("reference:\n  gap: 010\n", "['reference']['gap']", ": 010 is not allowed: YAML 1.1 reads it as 8"),
        ("maps:\n  rescue: yes\n", "['maps']['rescue']", ": yes is not allowed: YAML 1.1 reads it as True"),
        ("maps:\n  rescue: on\n", "['maps']['rescue']", ": on is not allowed: YAML 1.1 reads it as True"),
    ],
)
def test_a_config_file_with_a_repeated_key_or_yaml11_value_is_named_with_the_file(tmp_path, text, where, why):
    path = tmp_path / "override.yaml"
    path.write_text(text)
    with pytest.raises(cc.ConfigError) as err:
        cc.check(_shipped(), SCHEMA, files=[ROOT / "config" / "config.yaml", path])
    text = str(err.value)
    assert text.startswith(f"Error validating config file {path}: {where}{why}") and "\n" not in text, text


def test_config_files_read_as_written_pass(tmp_path):
    path = tmp_path / "override.yaml"
    path.write_text("reference:\n  gap: -0.0\nsolver:\n  gap_tol: 1e-12\n  max_periods: 1_000\nmaps:\n  rescue: true\n")
    assert cc.file_problem(path) is None
    assert cc.file_problem(ROOT / "config" / "config.yaml") is None
    assert cc.file_problem(ROOT / "config" / "ci.yaml") is None


# --- issue 33: limits at validation --------------------------------------------------------------
ROOT_RULE = "must be '.' or a relative path under results/ (the git-ignored scratch), such as results/ci"


@pytest.mark.parametrize(
    "root",
    [
        "/",
        "/tmp/out",
        "../out",
        "results",
        "results/",
        "results/../figures",
        "figures/ci",
        "paper",
        "src/out",
        "",
        "~/x",
    ],
)
def test_an_output_root_outside_the_scratch_is_refused(root):
    assert cc._output_root_problem(root) == (("output_root",), f": {root!r} is not allowed: {ROOT_RULE}")
    assert _refused(_set(_shipped(), ("output_root",), root)).endswith(
        f"['output_root']: {root!r} is not allowed: {ROOT_RULE}"
    )


@pytest.mark.parametrize("root", [".", "./", "results/ci", "./results/ci/", "results/a/b"])
def test_an_output_root_in_the_scratch_or_the_record_run_passes(root):
    assert cc._output_root_problem(root) is None


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        (
            ("sweep", "points"),
            10**9,
            "['sweep']['points']: 1000000000 is not allowed: 1000000000 sweep values; at most 10000",
        ),
        (
            ("verdict", "gap_step"),
            1e-9,
            "['verdict']['gap_step']: 1e-09 is not allowed: 16000000000 Algorithm No. 2 gap values from gap_min to "
            "gap_max; at most 10000",
        ),
        (
            ("maps", "theta"),
            {"parameter": "theta", "start": 0.5, "stop": 1.5, "points": 10**5},
            "['maps']['theta']: points x gap_points = 100000 x 100000 is not allowed: 10000000000 map cells; at most "
            "1000000",
        ),
        (
            ("claims_search", "map", "x_points"),
            2000,
            "['claims_search']['map']: x_points x y_points = 2000 x 81 is not allowed: 162000 map cells; at most 100000",
        ),
        (("design", "band_step"), 1e-9, "['design']['band_step']: 1e-09 is not allowed: 1000000001 theta values"),
        (("design", "response_points"), 1001, "['design']['response_points']: 1001 is not allowed: 1001 theta values"),
        (
            ("claims_search", "nearest", "ray_step"),
            1e-9,
            "['claims_search']['nearest']: (98 + rays) x ceil(ray_max / ray_step) = 398 x 120000000 is not allowed",
        ),
        (("performance", "compiled_speed_map_sizes"), [5000], "['performance']['compiled_speed_map_sizes'][0]: 5000"),
        (("performance", "reference_speed_repeats"), 10**6, "['performance']['reference_speed_repeats']: 1000000"),
    ],
)
def test_a_grid_too_large_is_named_with_its_bound(path, value, message):
    config = _shipped()
    if isinstance(value, dict):  # a map section: the grid's own keys changed, the gap columns too
        value = {**config[path[0]][path[1]], **value, "gap_points": 10**5}
    text = _refused(_set(config, path, value))
    assert message in text, text


def test_every_grid_key_beyond_its_bound_is_refused_naming_it():
    """Each grid that one key sets (a count or a step), pushed past its bound alone, stops the
    check with its key's path (or its section's, where the product of its keys is bounded)."""
    grids = cc.grid_sizes(cc._with_defaults(_shipped(), SCHEMA))
    keyed = [
        (path, limit) for path, shown, _, limit, _ in grids if isinstance(path[-1], (str, int)) and " " not in shown
    ]
    assert len(keyed) > 50
    for path, limit in keyed:
        config = _shipped()
        step = isinstance(path[-1], str) and path[-1].endswith("_step")
        text = _refused(_set(config, path, 1e-12 if step else limit + 1))
        where = text.removeprefix("Error validating config file: ").split(":")[0]
        named = "".join(f"[{p!r}]" for p in path)
        section = "".join(f"[{p!r}]" for p in path[:-1])
        assert where in (named, section), (path, text)


def test_a_claims_map_of_a_parameter_against_itself_is_refused():
    config = _set(_shipped(), ("claims_search", "map", "x"), "gap")
    config["claims_search"]["map"].update(x_start=-12.0, x_stop=-4.0)
    assert _refused(config).endswith(
        "['claims_search']['map']['y']: 'gap' is not allowed: must differ from x = 'gap' (a map of two parameters)"
    )
    config = _set(_shipped(), ("claims_search", "pair_maps", "theta_N", "y"), "theta")
    config["claims_search"]["pair_maps"]["theta_N"].update(y_start=0.85, y_stop=1.15)
    assert "['claims_search']['pair_maps']['theta_N']['y']: 'theta' is not allowed: must differ from x" in _refused(
        config
    )


def test_a_design_grid_without_the_reference_theta_is_refused_with_ones_that_hold_it():
    config = _set(_shipped(), ("design", "band_step"), 0.4)
    assert _refused(config).endswith(
        "['design']['band_step']: 0.4 is not allowed: the theta grid from 0.5 to 1.5 must contain the reference "
        "theta = 1 (such as 0.05, 0.025, 0.02)"
    )
    config = _set(_shipped(), ("design", "theta_start"), 1.2)
    assert "['design']: theta_start = 1.2, theta_stop = 1.5 is not allowed: the band must contain" in _refused(config)
    config = _set(_shipped(), ("reference", "theta"), 1.1)  # 0.5 to 1.5 in steps of 0.02 holds 1.1
    assert cc.check(config, SCHEMA)["reference"]["theta"] == 1.1


@pytest.mark.parametrize("step", [1.0, 0.5, 0.3, 0.25, 0.15, 0.1, 0.06, 0.05, 0.045, 0.025])
def test_the_reference_theta_check_agrees_with_the_design_job(monkeypatch, tmp_path, step):
    """The design chart's job (workflow/scripts/design_chart.py) refuses a grid without the
    reference theta before its sweeps; the config check refuses exactly the same grids."""
    import design_chart

    class Started(Exception):
        pass

    def started(*args, **kwargs):
        raise Started

    monkeypatch.setattr(design_chart, "gap_chart", started)
    config = _set(_shipped(), ("design", "band_step"), step)
    filled = cc._with_defaults(config, SCHEMA)
    with pytest.raises((ValueError, Started)) as job:
        design_chart.main(filled["reference"], filled["design"], tmp_path / "a", tmp_path / "b")
    accepted = cc.problem(config, SCHEMA) is None
    assert accepted == (job.type is Started), (step, str(job.value))


def test_an_output_root_resolved_outside_the_scratch_is_refused(tmp_path, monkeypatch):
    """A symbolic link under results/ to a directory outside the repository passed the check as
    written; the root is resolved first."""
    (tmp_path / "results").mkdir()
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "results" / "away").symlink_to(tmp_path / "elsewhere")
    (tmp_path / "results" / "here").mkdir()
    monkeypatch.chdir(tmp_path)
    problem = cc._output_root_problem("results/away")
    assert problem[0] == ("output_root",) and f"resolves to {tmp_path / 'elsewhere'}" in problem[1]
    assert cc._output_root_problem("results/here") is None and cc._output_root_problem("results/new/run") is None


def test_elastic_impacts_where_the_grids_hold_preloaded_stops_are_refused():
    """reference R = 1 passed the checker; the maps' preloaded points would then fail in their jobs."""
    text = _refused(_set(_shipped(), ("reference", "R"), 1.0))
    assert "['reference']['R']: 1.0 is not allowed: the workflow's grids hold preloaded stops" in text
    assert text.endswith("must be below 1")
    assert cc.check(_set(_shipped(), ("reference", "R"), 0.99), SCHEMA)["reference"]["R"] == 0.99


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("stiffness_drift", 0.5, "['design']['stiffness_drift']: 0.5 is greater than the maximum of 0.3"),
        ("damping_drift", -0.1, "['design']['damping_drift']: -0.1 is less than the minimum of 0"),
    ],
)
def test_the_absorbers_drifts_are_checked_and_reach_the_design_check(key, value, message, monkeypatch):
    """design.stiffness_drift and design.damping_drift: refused beyond the design command's ranges
    (the schema's bounds are the command's), and the design object's check sees the config's
    values (it once built the uncertainty without them, at their defaults)."""
    from impactdamper.studies.design import search_setup
    from impactdamper.studies.design.devices import RANGES

    assert message in _refused(_set(_shipped(), ("design", key), value))
    bounds = SCHEMA["properties"]["design"]["properties"][key]
    assert (bounds["minimum"], bounds["maximum"]) == RANGES[key]
    seen = []
    monkeypatch.setattr(search_setup, "check_object", lambda band, mu, delta1, unc, *rest: seen.append(unc))
    config = _set(_set(_shipped(), ("design", "stiffness_drift"), 0.12), ("design", "damping_drift"), 0.7)
    assert cc.problem(config, SCHEMA) is None
    assert (seen[-1].stiffness, seen[-1].damping) == (0.12, 0.7)
