"""The workflow's own cost (impactdamper.studies.performance.cost): Snakemake benchmark files
read back, the latest run's jobs kept, summed per rule and over the run, and rendered."""

import os

import pytest

from impactdamper.studies.performance import cost
from impactdamper.studies.performance.record import cost_macros, cost_page, cost_table

HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def _bench(directory, name: str, wall: float, cpu, end: float):
    path = directory / f"{name}.tsv"
    path.write_text(HEADER + f"{wall}\t0:00:00\t1\t1\t1\t1\t0\t0\t0\t{cpu}\n")
    os.utime(path, (end, end))
    return path


def test_the_latest_run_is_summed_by_rule_and_over_the_run(tmp_path):
    t = 1_000_000.0
    paths = [
        _bench(tmp_path, "sweep_alg1", 4.0, 3.0, t - 5000),  # an older run's job, not run since
        _bench(tmp_path, "compiled_warm_up", 3.0, 2.0, t + 3),  # this run's first job: starts at t
        _bench(tmp_path, "map_chunk-theta-0", 30.0, 29.0, t + 40),
        _bench(tmp_path, "map_chunk-theta-1", 20.0, 19.0, t + 40),
        _bench(tmp_path, "claims_pair_map-theta_N", 50.0, 95.0, t + 90),
        _bench(tmp_path, "fig2a-stated", 0.4, "NA", t + 91),  # too short for a sample
        _bench(tmp_path, "report", 20.0, 15.0, t + 120),
    ]
    exact = tmp_path / "jobs"
    exact.mkdir()
    (exact / "claims_pair_map-theta_N.json").write_text('{"cpu_s": 99.5, "end": %r}' % (t + 89.5))
    (exact / "map_chunk-theta-1.json").write_text('{"cpu_s": 5.0, "end": %r}' % (t - 4000))  # another run's
    jobs = cost.run_jobs(paths, exclude=["report"], exact_dir=exact)
    assert [j["rule"] for j in jobs] == ["compiled_warm_up", "map_chunk", "map_chunk", "claims_pair_map", "fig2a"]
    assert jobs[1]["wildcards"] == ["theta", "0"] and jobs[3]["wildcards"] == ["theta_N"]
    s = cost.summarize(jobs, top=2, cores=2)
    assert [j["cpu_source"] for j in jobs] == ["sampled", "sampled", "sampled", "exact", "sampled"]
    assert [r["rule"] for r in s["top"]] == ["claims_pair_map", "map_chunk"]  # by CPU time
    assert s["top"][1] == {"rule": "map_chunk", "jobs": 2, "wall_s": 50.0, "cpu_s": 48.0, "longest_s": 30.0}
    assert s["wall_s"] == pytest.approx(91.0 - 0.0)  # warm-up start (t + 0) to the figure's end (t + 91)
    assert s["cpu_s"] == pytest.approx(2.0 + 99.5 + 48.0) and s["unsampled_jobs"] == 1 and s["exact_jobs"] == 1
    assert s["busy"] == pytest.approx(s["cpu_s"] / (91.0 * 2))
    s["machine"] = {"load_average": [0.5, 0.4, 0.3], "cpu_count": 2}
    tex = cost_macros(s).tex()
    assert r"\newcommand{\CostWall}{1\,min 31\,s}" in tex and r"\newcommand{\CostJobs}{5}" in tex
    table = cost_table(s)
    assert r"claims pair map & 1 & 50 & 100 \\" in table
    assert r"whole run, first start to last end & 5 & 91 & 150 \\" in table


def test_a_file_that_is_not_a_benchmark_is_named(tmp_path):
    bad = tmp_path / "x.tsv"
    bad.write_text("a\tb\n1\t2\n")
    with pytest.raises(ValueError, match="not a Snakemake benchmark file"):
        cost._read_benchmark(bad)


def test_the_cost_page_lists_every_rule_costliest_first_with_its_definitions():
    summary = {
        "jobs": 3,
        "cores": 2,
        "wall_s": 75.0,
        "cpu_s": 130.0,
        "busy": 0.87,
        "machine": {"load_average": [1.5, 1.0, 0.5]},
        "excluded": ["report"],
        "rules": [
            {"rule": "b", "jobs": 1, "cpu_s": 10.0, "longest_s": 12.0, "wall_s": 12.0},
            {"rule": "a", "jobs": 2, "cpu_s": 120.0, "longest_s": 40.0, "wall_s": 70.0},
        ],
    }
    page = cost_page(summary)
    assert page.index("| `a` | 2 | 120.0 | 40.0 |") < page.index("| `b` | 1 | 10.0 | 12.0 |")
    assert "1 min 15 s (75 s)" in page and "2 min 10 s (130 s)" in page and "87 %" in page
    assert "`report`" in page and "\\," not in page
