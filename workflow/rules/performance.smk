# Stage: speed against error, and numerical stability on hard cases.
# The work-precision study (every method against a 40-digit mpmath reference), the cost
# growth of the exact solver, the hard-case suite and the reference-speed benchmark;
# then the report's macros and tables. Timings are CPU time (the minimum or median of repeated
# runs, each record with the machine's load): the timed rules take one core and share the
# machine with the other stages' jobs, as a whole-workflow run in a few minutes on two cores
# needs; only the compiled-solver benchmark's regime map, timed on two processes, takes both
# cores (rule performance_compiled_map, threads: 2) so that nothing else runs beside it. BLAS threads stay at 1 (4 x 4
# matrices gain nothing). Their outputs are benchmark data, not deterministic (listed in
# figures/nondeterministic.json).
# Convention: every script runs through `script:` and has a main() the tests call directly.

from impactdamper.studies.performance.compile_record import current_compile_record


rule performance_work_precision:
    input:
        script="workflow/scripts/work_precision.py",
        library=library(BASELINES, study("config", "performance/methods", "performance/workprecision"), REPORTING),
    output:
        json="results/benchmarks/work_precision.json",
        csv="figures/work_precision.csv",
    log:
        "logs/performance/work_precision.log",
    benchmark:
        benchmark_file("performance_work_precision")
    priority: 30
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        performance=parameters_json("performance"),
    script:
        "../scripts/work_precision.py"


rule fig_work_precision:
    input:
        script="workflow/scripts/fig_work_precision.py",
        library=library(BASELINES, study("performance/methods"), REPORTING),
        style=STYLE,
        csv="figures/work_precision.csv",
        json="results/benchmarks/work_precision.json",
    output:
        pdf="figures/work_precision.pdf",
        png="figures/work_precision.png",
    log:
        "logs/performance/fig_work_precision.log",
    benchmark:
        benchmark_file("fig_work_precision")
    conda:
        ENV
    params:
        performance=parameters_json("performance"),
    script:
        "../scripts/fig_work_precision.py"


rule performance_cost_growth:
    input:
        script="workflow/scripts/cost_growth.py",
        library=library(BASELINES, study("config", "performance/methods", "performance/workprecision"), REPORTING),
    output:
        json="results/benchmarks/cost_growth.json",
        csv="figures/cost_growth.csv",
    log:
        "logs/performance/cost_growth.log",
    benchmark:
        benchmark_file("performance_cost_growth")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        performance=parameters_json("performance"),
    script:
        "../scripts/cost_growth.py"


rule fig_cost_growth:
    input:
        script="workflow/scripts/fig_cost_growth.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        csv="figures/cost_growth.csv",
    output:
        pdf="figures/cost_growth.pdf",
        png="figures/cost_growth.png",
    log:
        "logs/performance/fig_cost_growth.log",
    benchmark:
        benchmark_file("fig_cost_growth")
    conda:
        ENV
    script:
        "../scripts/fig_cost_growth.py"


rule performance_hardcases:
    input:
        script="workflow/scripts/hardcases.py",
        library=library(
            BASELINES, study("config", "performance/hardcases", "performance/hardcase_checks", "vocabulary"), REPORTING
        ),
    output:
        csv="figures/hardcases.csv",
        json="results/benchmarks/hardcases.json",
        tex="paper/generated/hardcases_table.tex",
    log:
        "logs/performance/hardcases.log",
    benchmark:
        benchmark_file("performance_hardcases")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
    script:
        "../scripts/hardcases.py"


rule performance_reference_speed:
    input:
        script="workflow/scripts/reference_speed.py",
        library=library(BASELINES, REPORTING),
    output:
        "results/benchmarks/reference_speed.json",
    log:
        "logs/performance/reference_speed.log",
    benchmark:
        benchmark_file("performance_reference_speed")
    conda:
        ENV
    params:
        repeats=config["performance"]["reference_speed_repeats"],
        ivp_repeats=config["performance"]["reference_speed_ivp_repeats"],
        targets=json.dumps(config["performance"]["reference_speed_targets"], sort_keys=True),
    script:
        "../scripts/reference_speed.py"


# The JIT compile time of the compiled solver (its kernels compiled into a fresh numba cache of
# their own, in a subprocess), and the time to load them from that cache: measured once at set-up
# (tools/setup.sh) into SETUP_COMPILE_RECORD, which the report reads while it is current (the
# same kernels' sources and numba); where it is missing or stale, rule performance_compile_time
# measures it in the run (one core, beside the other jobs: a compile is one process).
SETUP_COMPILE_RECORD = str(Path(workflow.basedir) / "results" / "setup" / "compile_time.json")
COMPILE_TIME = (
    SETUP_COMPILE_RECORD if current_compile_record(SETUP_COMPILE_RECORD) else "results/benchmarks/compile_time.json"
)


rule performance_compile_time:
    input:
        script="workflow/scripts/compiled_speed.py",
        library=library(
            BASELINES,
            study(
                "performance/compile_record",
                "performance/compiled_speed",
                "performance/front_door_speed",
                "performance/timing",
            ),
            REPORTING,
        ),
    output:
        "results/benchmarks/compile_time.json",
    log:
        "logs/performance/compile_time.log",
    benchmark:
        benchmark_file("performance_compile_time")
    conda:
        ENV
    params:
        compile_only=True,
    script:
        "../scripts/compiled_speed.py"


# The maps' settle settings (keys of the config's maps section), which the compiled-solver
# benchmark's maps and batch use.
MAP_SETTLE_KEYS = ("settle_tol", "max_periods", "max_periods_after_nonperiodic", "max_period_multiple")


# The compiled solver's regime maps (core/compiled, analysis/batch.py) timed on two processes
# (hence threads: 2): the one part of its benchmark that needs both cores to itself. It has the
# highest priority, so that it runs right after the warm-up, on an idle machine (a job that takes
# both cores would otherwise wait until no one-core job is left), and it is short.
rule performance_compiled_map:
    input:
        script="workflow/scripts/compiled_speed.py",
        library=library(
            BASELINES,
            study(
                "performance/compile_record",
                "performance/compiled_speed",
                "performance/front_door_speed",
                "performance/timing",
            ),
            REPORTING,
        ),
    output:
        "results/benchmarks/compiled_map.json",
    log:
        "logs/performance/compiled_map.log",
    benchmark:
        benchmark_file("performance_compiled_map")
    priority: 1000
    conda:
        ENV
    threads: 2
    params:
        maps_only=True,
        map_sizes=config["performance"]["compiled_speed_map_sizes"],
        map_repeats=config["performance"]["compiled_speed_map_repeats"],
        targets=json.dumps(config["performance"]["compiled_speed_targets"], sort_keys=True),
        maps=json.dumps({key: config["maps"][key] for key in MAP_SETTLE_KEYS}, sort_keys=True),
    script:
        "../scripts/compiled_speed.py"


# The compiled solver's speed against its targets: per impact, the reference steady state, the
# first 10 impacts, the front door, and the maps (rule performance_compiled_map's, with their
# DOP853 and pure-Python estimates); one core, beside the other jobs (its timings are CPU time,
# with the load recorded); the JIT compile time is the set-up's or rule
# performance_compile_time's.
rule performance_compiled_speed:
    input:
        script="workflow/scripts/compiled_speed.py",
        library=library(
            BASELINES,
            study(
                "performance/compile_record",
                "performance/compiled_speed",
                "performance/front_door_speed",
                "performance/timing",
            ),
            REPORTING,
        ),
        maps="results/benchmarks/compiled_map.json",
    output:
        "figures/compiled_speed.json",
    log:
        "logs/performance/compiled_speed.log",
    benchmark:
        benchmark_file("performance_compiled_speed")
    conda:
        ENV
    params:
        repeats=config["performance"]["compiled_speed_repeats"],
        map_sizes=config["performance"]["compiled_speed_map_sizes"],
        targets=json.dumps(config["performance"]["compiled_speed_targets"], sort_keys=True),
        batch_points=config["performance"]["compiled_speed_batch_points"],
        maps=json.dumps({key: config["maps"][key] for key in MAP_SETTLE_KEYS}, sort_keys=True),
    script:
        "../scripts/compiled_speed.py"


rule performance_report:
    input:
        script="workflow/scripts/performance_report.py",
        library=library(BASELINES, study("performance/methods", "performance/record", "performance/summary"), REPORTING),
        work_precision="results/benchmarks/work_precision.json",
        cost_growth="results/benchmarks/cost_growth.json",
        hardcases="results/benchmarks/hardcases.json",
        reference_speed="results/benchmarks/reference_speed.json",
        compiled_speed="figures/compiled_speed.json",
        compile_time=COMPILE_TIME,
        warm_up=COMPILED_WARM_UP,
    output:
        record="results/report/performance.json",
        macros="paper/generated/performance_macros.tex",
        table="paper/generated/workprecision_table.tex",
        compiled_table="paper/generated/compiled_speed_table.tex",
        summary="results/benchmarks/performance_summary.json",
    log:
        "logs/performance/performance_report.log",
    benchmark:
        benchmark_file("performance_report")
    conda:
        ENV
    params:
        performance=parameters_json("performance"),
    script:
        "../scripts/performance_report.py"


ALL_TARGETS.extend(
    [
        "figures/work_precision.pdf",
        "figures/work_precision.png",
        "figures/work_precision.csv",
        "figures/cost_growth.pdf",
        "figures/cost_growth.png",
        "figures/cost_growth.csv",
        "figures/hardcases.csv",
        "paper/generated/hardcases_table.tex",
        "paper/generated/performance_macros.tex",
        "paper/generated/workprecision_table.tex",
        "paper/generated/compiled_speed_table.tex",
        "results/benchmarks/reference_speed.json",
        "figures/compiled_speed.json",
    ]
)
