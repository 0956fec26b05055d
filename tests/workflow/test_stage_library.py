"""The library parts the workflow's stages share: records (CSV, JSON, the start of a script),
LaTeX macro records, the figure-saving helper, the sweep points' npz record and the gap scan
of the replication checks. Closed-form or hand-checked cases first."""

import json
import logging
import math
import types
from dataclasses import fields

import numpy as np
import pytest

from impactdamper import Parameters
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.sweeps import two_way_sweep
from impactdamper.reporting import latex, records
from impactdamper.reporting.plotting import finish_figure, use_style
from impactdamper.studies.sweeps import gapsweep


# --- the gap scan: a closed-form gap -------------------------------------------------------------
from impactdamper.studies.replication import crosscheck


@pytest.mark.parametrize("samples", [400, 4000])
def test_gap_sign_scan_finds_the_roots_of_a_cosine(samples):
    """gap(s) = cos(2 pi s) is negative on (1/4, 3/4): both ends to the scan's xtol (1e-14)."""
    scan = crosscheck.gap_sign_scan(lambda s: math.cos(2 * math.pi * s), samples)
    assert len(scan.negative_intervals) == 1
    lo, hi = scan.negative_intervals[0]
    assert abs(lo - 0.25) <= 1e-13 and abs(hi - 0.75) <= 1e-13, (lo, hi)
    assert scan.crossings == (lo, hi)
    assert scan.interior_minima == [pytest.approx(-1.0, abs=1e-4)]


def test_gap_sign_scan_open_ends_and_no_root():
    """Negative at the scan's start: the interval opens at 0; never negative: no interval."""
    scan = crosscheck.gap_sign_scan(lambda s: s - 0.5, 100)
    assert scan.negative_intervals == ((0.0, pytest.approx(0.5, abs=1e-14)),)
    assert crosscheck.gap_sign_scan(lambda s: 1.0 + s, 100).negative_intervals == ()


# --- records ------------------------------------------------------------------------------------
def test_csv_cells_and_booleans(tmp_path):
    path = tmp_path / "t.csv"
    rows = [{"a": 1.0 / 3.0, "b": True, "c": None}, {"a": math.nan, "b": False, "c": "x"}]
    records.write_csv(path, ["a", "b", "c"], rows)
    assert path.read_text() == "a,b,c\n0.333333333333,true,\n,false,x\n"
    records.write_csv(path, ["a", "b", "c"], rows, booleans="digits")
    assert path.read_text() == "a,b,c\n0.333333333333,1,\n,0,x\n"
    back = records.read_csv(path)
    assert records.cell_float(back[0]["a"]) == pytest.approx(1 / 3, rel=1e-11)
    assert math.isnan(records.cell_float(back[1]["a"]))


def test_json_keys_order_and_non_finite(tmp_path):
    path = tmp_path / "t.json"
    records.write_json(path, {"b": np.float64(math.inf), "a": np.arange(2)}, sort_keys=False, indent=2)
    assert path.read_text() == '{\n  "b": null,\n  "a": [\n    0,\n    1\n  ]\n}\n'
    assert records.json_float(records.read_json(path)["b"]) == math.inf


def test_start_stage_reads_the_config_params_and_logs(tmp_path):
    params = types.SimpleNamespace(items=lambda: [("reference", '{"gap": -5.8}'), ("case", "stated")])
    sm = types.SimpleNamespace(log=[str(tmp_path / "logs" / "x.log")], params=params)
    cfg, log = records.start_stage(sm, "test_start_stage")
    assert cfg == {"reference": {"gap": -5.8}, "case": "stated"}
    log.info("hello")
    for h in logging.getLogger("test_start_stage").handlers:
        h.flush()
    assert (tmp_path / "logs" / "x.log").read_text() == "hello\n"


def test_run_stage_hands_main_the_jobs_values(tmp_path):
    """A script's __main__ (records.run_stage): each path of the spec is the job's value, in
    order, converted where asked, a missing optional wildcard None, keywords by name, callables
    of the job, and the config sections read back as dicts."""
    params = types.SimpleNamespace(items=lambda: [("reference", '{"gap": -5.8}'), ("stated_gap", "-5.8")])
    job = types.SimpleNamespace(
        log=[str(tmp_path / "x.log")],
        params=params,
        input=types.SimpleNamespace(csv="in.csv", maps=("a.csv", "b.csv")),
        output=types.SimpleNamespace(pdf="out.pdf"),
        wildcards=types.SimpleNamespace(chunk="3"),
        threads=2,
    )
    got = []

    def main(*args, **kwargs):
        got.append((args, kwargs))
        return "result"

    out = records.run_stage(
        job,
        main,
        ("params.reference input.csv wildcards.chunk:int", lambda j: j.threads + 1),
        "input.maps:list params.stated_gap:float name=wildcards.name? out=output.pdf",
        log="say",
        logger="test_run_stage",  # progress lines to the log file (without: the standard error)
    )
    assert out == "result"
    ((args, kwargs),) = got
    assert args == ({"gap": -5.8}, "in.csv", 3, 3, ["a.csv", "b.csv"], -5.8)
    assert kwargs["name"] is None and kwargs["out"] == "out.pdf"
    kwargs["log"]("hello")  # "say": a progress line to the stage's logger
    for h in logging.getLogger("test_run_stage").handlers:
        h.flush()
    assert (tmp_path / "x.log").read_text() == "hello\n"
    with pytest.raises(AttributeError):  # a path that is not optional must exist
        records.run_stage(job, main, "wildcards.name", logger="test_run_stage")
    for h in logging.getLogger("test_run_stage").handlers:
        h.close()


# --- LaTeX macro records ------------------------------------------------------------------------
def test_macro_file_renders_tex_and_text_from_one_record(tmp_path):
    m = latex.MacroFile(["% a comment\n", ("Alpha", latex.sci(7.2e-12))])
    m.add("Beta", latex.MISSING)
    m.add("Gamma", r"S $\to$ c/1")
    m.add("Delta", latex.tex_time(2.5e-4))
    records.write_json(tmp_path / "r.json", m.record("test"), sort_keys=False)
    record = records.read_json(tmp_path / "r.json")
    assert latex.render_macros(record) == (
        "% a comment\n\\newcommand{\\Alpha}{7.2 \\times 10^{-12}}\n"
        "\\newcommand{\\Beta}{\\mbox{--}}\n\\newcommand{\\Gamma}{S $\\to$ c/1}\n"
        "\\newcommand{\\Delta}{250\\,\\textmu s}\n"
    )
    assert m.tex() == latex.render_macros(record)
    assert latex.macro_texts(record) == {"Alpha": "7.2e-12", "Beta": "–", "Gamma": "S -> c/1", "Delta": "250 µs"}


def test_macro_names_are_letters_only():
    with pytest.raises(ValueError, match=r"`name` = 'A1' is not allowed"):
        latex.MacroFile().add("A1", "1")


# --- figures ------------------------------------------------------------------------------------
def test_finish_figure_saves_closes_and_is_deterministic(tmp_path):
    plt = use_style()
    said = []
    digests = []
    for run in range(2):
        fig, ax = plt.subplots()
        ax.plot([0, 1], [0, 1])
        out = finish_figure(fig, tmp_path / f"f{run}.pdf", tmp_path / f"f{run}.png", log=said.append)
        assert [p.name for p in out] == [f"f{run}.pdf", f"f{run}.png"]
        assert not plt.fignum_exists(fig.number)
        digests.append([p.read_bytes() for p in out])
    assert digests[0] == digests[1]
    assert said[0] == f"wrote {tmp_path / 'f0.pdf'}, {tmp_path / 'f0.png'}"


# --- the sweep's points -------------------------------------------------------------------------
def test_sweep_points_round_trip_through_npz(tmp_path):
    """Every field of every point comes back equal (arrays bit for bit), so the transition
    bisection starts from the same states as with the points in memory."""
    res = two_way_sweep(Parameters(), "gap", np.linspace(-34.0, 14.0, 6), settings=SweepSettings())
    path = tmp_path / "points.npz"
    gapsweep.write_points(path, {"up": res["up"], "down": res["down"]})
    back = gapsweep.read_points(path)
    with np.load(path, allow_pickle=False) as data:  # plain arrays: no pickled objects
        assert all(data[k].dtype != object for k in data.keys())
    for d in ("up", "down"):
        assert len(back[d]) == len(res[d])
        for a, b in zip(res[d], back[d]):
            for f in fields(a):
                x, y = getattr(a, f.name), getattr(b, f.name)
                if f.name == "cycle":
                    assert len(x) == len(y) and all(np.array_equal(u, v) for u, v in zip(x, y)), f.name
                elif isinstance(x, (np.ndarray, float, tuple)) and x is not None:
                    assert np.array_equal(x, y, equal_nan=True), f.name
                else:
                    assert x == y, f.name
    assert {p.label for p in back["up"]} >= {"stuck", "0/1"}


def test_regime_of_label():
    assert [gapsweep.regime_of_label(x) for x in ("stuck", "0/1", "np", "err", "1/1", "c/2", "3/2")] == [
        "stuck",
        "no_contact",
        "nonperiodic",
        "failed",
        "single_impact",
        "chatter",
        "multi_impact",
    ]
    assert gapsweep.runs([1, 2, 3, 4], ["a", "a", "b", "a"]) == [("a", 1, 2, 2), ("b", 3, 3, 1), ("a", 4, 4, 1)]


def test_config_errors_name_the_argument():
    from impactdamper.studies.config import chunk_indices

    with pytest.raises(ValueError, match=r"`chunk` = 3 is not allowed: must be in \[0, 3\)"):
        chunk_indices(10, 3, 3)
    assert (
        json.dumps([list(chunk_indices(10, 3, i)) for i in range(3)], default=int)
        == "[[0, 1, 2, 3], [4, 5, 6], [7, 8, 9]]"
    )


# --- the transitions' second, numeric values against the closed form -------------------------------
def test_numeric_thresholds_match_the_closed_form():
    """(a) The joined bodies' least contact force is zero at the analytic lift-off gap; (b) the
    free forced response's largest x2p - x1p is U1/x_st, the analytic first-contact gap. Both to
    1e-9 (relative to the force scale, and in units of x_st): the sampled-and-refined extremum
    resolves the phase to ~1e-14 T."""
    from impactdamper.analysis.sweeps import with_value
    from impactdamper.analysis.transitions import no_contact_gap, stuck_liftoff_gap
    from impactdamper.studies.sweeps import transitions as transitions

    base = Parameters()
    liftoff = stuck_liftoff_gap(base)
    assert abs(transitions._least_contact_force(with_value(base, "gap", liftoff))) <= 1e-9
    assert transitions._least_contact_force(with_value(base, "gap", liftoff - 1.0)) > 1e-3  # pressed: F > 0
    assert abs(transitions._largest_relative_displacement(base) - no_contact_gap(base)) <= 1e-9


def test_a_jobs_exact_cpu_time_is_recorded_when_its_script_ends(tmp_path, monkeypatch):
    """A Snakemake job (an object with ``rule``) records its CPU time, its own and its waited-for
    children's, under the job's name when the script ends (an atexit hook, not in a forked
    worker); the tests' fake jobs (no ``rule``) record nothing."""
    import atexit
    import json
    import subprocess
    import sys

    hooks = []
    monkeypatch.setattr(atexit, "register", lambda f, *a: hooks.append((f, a)))
    monkeypatch.chdir(tmp_path)
    params = types.SimpleNamespace(items=lambda: [])
    sm = types.SimpleNamespace(
        log=[str(tmp_path / "x.log")], params=params, rule="map_chunk", wildcards={"map": "theta", "chunk": "3"}
    )
    records.start_stage(sm, "test_job_cost")
    fake = types.SimpleNamespace(log=[str(tmp_path / "y.log")], params=params)
    records.start_stage(fake, "test_job_cost_fake")
    assert len(hooks) == 1 and records.job_name("map_chunk", {"map": "theta", "chunk": "3"}) == "map_chunk-3-theta"
    before = records._job_cpu_seconds()
    subprocess.run([sys.executable, "-c", "sum(range(3_000_000))"], check=True)  # a waited-for child
    ((f, args),) = hooks
    f(*args)
    got = json.loads((tmp_path / records.JOB_COST_DIR / "map_chunk-3-theta.json").read_text())
    assert got["children_s"] > before["children_s"] and got["cpu_s"] == got["self_s"] + got["children_s"]
    for h in logging.getLogger("test_job_cost").handlers + logging.getLogger("test_job_cost_fake").handlers:
        h.close()
