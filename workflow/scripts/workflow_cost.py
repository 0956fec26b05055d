"""The workflow's own cost: every job's Snakemake benchmark (``results/benchmarks/rules/``), with
the exact CPU time each Python job recorded itself (``results/benchmarks/jobs/``), gathered into
the rules' wall and CPU time (:mod:`impactdamper.studies.performance.cost`), for the report's
table of the costliest rules and the run's total.

The run is the jobs since the latest start of the kernels' warm-up (its first job). This job
runs after every other job but the report and the README summary, which read its outputs: their
own cost cannot be in it.

Outputs: ``figures/workflow_cost.json`` (every rule's cost, the run's wall and CPU time, the
machine; timings, not deterministic), ``paper/generated/workflow_cost_table.tex`` (the ten
costliest rules and the run), ``paper/generated/workflow_cost_macros.tex`` and its record
``results/report/workflow_cost.json``, and the repository's page ``docs/WORKFLOW_COST.md`` (every
rule's cost, with the definitions; the report keeps one sentence of it).
"""

from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import JOB_COST_DIR, machine, run_stage, write_json
from impactdamper.studies.performance import cost
from impactdamper.studies.performance.record import cost_macros, cost_page, cost_table

RECORD_WHAT = "the workflow's own cost: the costliest rules' wall and CPU time and the run's total"


def main(
    benchmarks: str,
    exclude: list,
    cores: int,
    top: int,
    out_json,
    out_table,
    out_macros,
    out_record,
    out_page=None,
    log=print,
) -> dict:
    paths = sorted(Path(benchmarks).glob("*.tsv"))
    jobs = cost.run_jobs(paths, exclude=exclude, exact_dir=JOB_COST_DIR)
    summary = cost.summarize(jobs, top=int(top), cores=int(cores) or None)
    summary["machine"] = machine()
    summary["excluded"] = list(exclude)
    summary["benchmarks"] = str(benchmarks)
    summary["job_list"] = jobs
    write_json(out_json, summary, indent=2)
    Path(out_table).parent.mkdir(parents=True, exist_ok=True)
    Path(out_table).write_text(cost_table(summary))
    record = cost_macros(summary).record(RECORD_WHAT)
    write_json(out_record, record, sort_keys=False)
    Path(out_macros).write_text(render_macros(record))
    if out_page is not None:
        Path(out_page).write_text(cost_page(summary))
    log(
        f"{summary['jobs']} jobs of {len(summary['rules'])} rules: wall {summary['wall_s']:.0f} s "
        f"(first start to last end), cpu {summary['cpu_s']:.0f} s; costliest "
        + ", ".join(f"{r['rule']} {r['cpu_s']:.0f} s" for r in summary["top"][:5])
    )
    return summary


JOB = (
    "params.benchmarks params.exclude:list params.cores:int params.top:int output.json output.table "
    "output.macros output.record out_page=output.page log=say"
)

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
