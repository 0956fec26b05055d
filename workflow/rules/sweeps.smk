# Stage: gap sweeps and regime maps. The gap Delta0/x_st is swept up and down over
# every regime of the reference case (config: sweep), with random initial states, transitions
# bisected and checked against analytic values; two-parameter maps (config: maps) run as
# chunks, one job each (wildcards map, chunk), gathered afterwards, so the same DAG runs on a
# cluster (profiles/slurm); the chunks run the compiled batch (after rule compiled_warm_up), each
# map computed where its labels change (impactdamper.analysis.adaptive). Benchmarks are timed
# inside the jobs (results/benchmarks/). The gap sweep and its transitions head a long chain of
# jobs (sweep, transitions, report): a high priority, so that they start first. The sweep and
# the transitions take one core each (the sweep's two directions one after the other; a job's
# processes are its threads, two where a profile sets them, as the Slurm one does): a two-core
# job waits until no one-core job is left, and then runs alone (the sweep ran at the end and
# the transitions after it, on one core).
# Convention: every script runs through `script:` and has a main() the tests call directly.

SWEEP_MAPS = ["theta", "damping"]
SWEEP_MAP_PATTERN = "|".join(SWEEP_MAPS)


# The compiled kernels, compiled (or loaded from numba's cache) once before the jobs that run
# them: the map chunks here and the other stages' jobs (common.smk, COMPILED_WARM_UP).
rule compiled_warm_up:
    input:
        script="workflow/scripts/compiled_warm_up.py",
        library=library_sources(REPORTING),
    output:
        json=COMPILED_WARM_UP,
    log:
        "logs/compiled/warm_up.log",
    benchmark:
        benchmark_file("compiled_warm_up")
    conda:
        ENV
    script:
        "../scripts/compiled_warm_up.py"


rule sweep_gap:
    input:
        script="workflow/scripts/sweep_gap.py",
        library=library(study("config", "sweeps/gapsweep"), REPORTING),
    output:
        csv="figures/sweep_gap.csv",
        settings="figures/sweep_gap_settings.json",
        points="results/sweeps/sweep_points.npz",
        timing="results/benchmarks/sweep_timing.json",
    log:
        "logs/sweeps/sweep_gap.log",
    benchmark:
        benchmark_file("sweep_gap")
    priority: 70
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
        target_wall_s=config["performance"]["sweep_target_wall_s"],
    script:
        "../scripts/sweep_gap.py"


rule sweep_random_chunk:
    input:
        script="workflow/scripts/sweep_random.py",
        library=library(study("config", "sweeps/gapsweep"), REPORTING),
    output:
        csv="results/sweeps/random_{chunk}.csv",
    log:
        "logs/sweeps/random_{chunk}.log",
    benchmark:
        benchmark_file("sweep_random_chunk", "chunk")
    wildcard_constraints:
        chunk=r"\d+",
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
    script:
        "../scripts/sweep_random.py"


rule sweep_random:
    input:
        script="workflow/scripts/gather_csv.py",
        library=library(REPORTING),
        chunks=random_chunk_files,
    output:
        csv="figures/sweep_random.csv",
    log:
        "logs/sweeps/random_gather.log",
    benchmark:
        benchmark_file("sweep_random")
    conda:
        ENV
    script:
        "../scripts/gather_csv.py"


rule sweep_alg1:
    input:
        script="workflow/scripts/sweep_alg1.py",
        library=library(study("config", "sweeps/gapsweep"), REPORTING),
    output:
        csv="figures/sweep_alg1.csv",
    log:
        "logs/sweeps/sweep_alg1.log",
    benchmark:
        benchmark_file("sweep_alg1")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
    script:
        "../scripts/sweep_alg1.py"


rule sweep_transitions:
    input:
        script="workflow/scripts/sweep_transitions.py",
        library=library(study("config", "sweeps/gapsweep", "sweeps/transitions"), REPORTING),
        points="results/sweeps/sweep_points.npz",
    output:
        csv="figures/sweep_transitions.csv",
        json="figures/sweep_checks.json",
    log:
        "logs/sweeps/sweep_transitions.log",
    benchmark:
        benchmark_file("sweep_transitions")
    priority: 50
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
    script:
        "../scripts/sweep_transitions.py"


rule map_chunk:
    input:
        script="workflow/scripts/map_chunk.py",
        library=library(study("config", "sweeps/gapsweep", "sweeps/mapchunk"), REPORTING),
    output:
        csv="results/maps/{map}/chunk_{chunk}.csv",
        json="results/maps/{map}/chunk_{chunk}.json",
    log:
        "logs/maps/{map}_chunk_{chunk}.log",
    benchmark:
        benchmark_file("map_chunk", "map", "chunk")
    wildcard_constraints:
        map=SWEEP_MAP_PATTERN,
        chunk=r"\d+",
    priority: 30
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        maps=parameters_json("maps"),
    script:
        "../scripts/map_chunk.py"


rule map_gather:
    input:
        script="workflow/scripts/map_gather.py",
        library=library(REPORTING),
        csvs=map_chunk_files,
        jsons=map_chunk_timings,
    output:
        csv="figures/map_{map}.csv",
        settings="figures/map_{map}_settings.json",
        timing="results/benchmarks/map_{map}_timing.json",
    log:
        "logs/maps/{map}_gather.log",
    benchmark:
        benchmark_file("map_gather", "map")
    wildcard_constraints:
        map=SWEEP_MAP_PATTERN,
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        maps=parameters_json("maps"),
    script:
        "../scripts/map_gather.py"


rule map_curves:
    input:
        script="workflow/scripts/map_curves.py",
        library=library(study("config", "sweeps/gapsweep"), REPORTING),
    output:
        csv="figures/map_{map}_curves.csv",
    log:
        "logs/maps/{map}_curves.log",
    benchmark:
        benchmark_file("map_curves", "map")
    wildcard_constraints:
        map=SWEEP_MAP_PATTERN,
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        maps=parameters_json("maps"),
    script:
        "../scripts/map_curves.py"


# Every boundary of a map as a curve (config: boundaries): seeded from the special points of
# the branches found on a few rows, followed across the plane by two-parameter continuation;
# the closed forms sampled. One job per map; then the curves read against both maps and checked
# by brute-force simulation.
rule boundaries:
    input:
        script="workflow/scripts/boundaries.py",
        library=library(study("config", "sweeps/gapsweep"), REPORTING),
    output:
        csv="figures/boundaries_{map}.csv",
        curves="results/boundaries/{map}.pkl",
        timing="results/boundaries/{map}_timing.json",
    log:
        "logs/maps/boundaries_{map}.log",
    benchmark:
        benchmark_file("boundaries", "map")
    wildcard_constraints:
        map=SWEEP_MAP_PATTERN,
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        maps=parameters_json("maps"),
        boundaries=parameters_json("boundaries"),
        orbits=parameters_json("orbits"),
    script:
        "../scripts/boundaries.py"


rule boundaries_check:
    input:
        script="workflow/scripts/boundaries_check.py",
        library=library(
            study(
                "config",
                "intervals",
                "sweeps/branches",
                "sweeps/gapsweep",
                "sweeps/results",
                "sweeps/boundary_report",
                "vocabulary",
            ),
            REPORTING,
        ),
        maps=expand("figures/map_{map}.csv", map=SWEEP_MAPS),
        csvs=expand("figures/boundaries_{map}.csv", map=SWEEP_MAPS),
        curves=expand("results/boundaries/{map}.pkl", map=SWEEP_MAPS),
        timings=expand("results/boundaries/{map}_timing.json", map=SWEEP_MAPS),
    output:
        json="figures/boundaries_check.json",
        macros="paper/generated/boundaries_macros.tex",
        table="paper/generated/boundaries_codim2.tex",
    log:
        "logs/maps/boundaries_check.log",
    benchmark:
        benchmark_file("boundaries_check")
    conda:
        ENV
    params:
        boundaries=parameters_json("boundaries"),
        names=SWEEP_MAPS,
    script:
        "../scripts/boundaries_check.py"


rule fig_sweep_bifurcation:
    input:
        script="workflow/scripts/fig_sweep_bifurcation.py",
        library=library(study("config", "vocabulary"), REPORTING),
        style=STYLE,
        sweep="figures/sweep_gap.csv",
        random="figures/sweep_random.csv",
        alg1="figures/sweep_alg1.csv",
        checks="figures/sweep_checks.json",
        located="figures/located_case.json",
        lyapunov="figures/lyapunov_sweep.csv",
    output:
        pdf="figures/sweep_bifurcation.pdf",
        png="figures/sweep_bifurcation.png",
    log:
        "logs/sweeps/fig_sweep_bifurcation.log",
    benchmark:
        benchmark_file("fig_sweep_bifurcation")
    conda:
        ENV
    params:
        stated_gap=config["reference"]["gap"],
    script:
        "../scripts/fig_sweep_bifurcation.py"


rule fig_sweep_regimes:
    input:
        script="workflow/scripts/fig_sweep_regimes.py",
        library=library(study("sweeps/gapsweep", "vocabulary"), REPORTING),
        style=STYLE,
        sweep="figures/sweep_gap.csv",
        random="figures/sweep_random.csv",
    output:
        pdf="figures/sweep_regimes.pdf",
        png="figures/sweep_regimes.png",
    log:
        "logs/sweeps/fig_sweep_regimes.log",
    benchmark:
        benchmark_file("fig_sweep_regimes")
    conda:
        ENV
    script:
        "../scripts/fig_sweep_regimes.py"


rule fig_sweep_suppression:
    input:
        script="workflow/scripts/fig_sweep_suppression.py",
        style=STYLE,
        library=library(study("config", "vocabulary"), REPORTING),
        sweep="figures/sweep_gap.csv",
        random="figures/sweep_random.csv",
    output:
        pdf="figures/sweep_suppression.pdf",
        png="figures/sweep_suppression.png",
    log:
        "logs/sweeps/fig_sweep_suppression.log",
    benchmark:
        benchmark_file("fig_sweep_suppression")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
    script:
        "../scripts/fig_sweep_suppression.py"


rule fig_regime_map:
    input:
        script="workflow/scripts/fig_regime_map.py",
        library=library(
            study("config", "intervals", "sweeps/branches", "sweeps/gapsweep", "sweeps/results", "vocabulary"),
            REPORTING,
        ),
        style=STYLE,
        map="figures/map_{map}.csv",
        curves="figures/map_{map}_curves.csv",
        located="figures/located_case.json",
        boundaries="figures/boundaries_{map}.csv",
    output:
        pdf="figures/map_{map}.pdf",
        png="figures/map_{map}.png",
    log:
        "logs/maps/fig_map_{map}.log",
    benchmark:
        benchmark_file("fig_regime_map", "map")
    wildcard_constraints:
        map=SWEEP_MAP_PATTERN,
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
    script:
        "../scripts/fig_regime_map.py"


rule sweep_report:
    input:
        script="workflow/scripts/sweep_report.py",
        library=library(
            study(
                "config",
                "intervals",
                "sweeps/branches",
                "sweeps/gapsweep",
                "sweeps/record",
                "sweeps/results",
                "vocabulary",
            ),
            REPORTING,
        ),
        sweep="figures/sweep_gap.csv",
        transitions="figures/sweep_transitions.csv",
        checks="figures/sweep_checks.json",
        settings="figures/sweep_gap_settings.json",
        special="figures/orbit_special_points.csv",
        maps=expand("figures/map_{map}.csv", map=SWEEP_MAPS),
        map_curves=expand("figures/map_{map}_curves.csv", map=SWEEP_MAPS),
        map_settings=expand("figures/map_{map}_settings.json", map=SWEEP_MAPS),
        sweep_timing="results/benchmarks/sweep_timing.json",
        map_timings=expand("results/benchmarks/map_{map}_timing.json", map=SWEEP_MAPS),
    output:
        record="results/report/sweeps.json",
        macros="paper/generated/sweep_macros.tex",
        table="paper/generated/sweep_transitions.tex",
        timing="paper/generated/sweep_timing.tex",
    log:
        "logs/sweeps/sweep_report.log",
    benchmark:
        benchmark_file("sweep_report")
    conda:
        ENV
    script:
        "../scripts/sweep_report.py"


SWEEP_TARGETS = (
    expand("figures/sweep_{fig}.{ext}", fig=["bifurcation", "regimes", "suppression"], ext=["pdf", "png"])
    + expand("figures/map_{map}.{ext}", map=SWEEP_MAPS, ext=["pdf", "png"])
    + [
        "paper/generated/sweep_macros.tex",
        "paper/generated/sweep_transitions.tex",
        "paper/generated/sweep_timing.tex",
        "paper/generated/boundaries_macros.tex",
        "paper/generated/boundaries_codim2.tex",
    ]
)


# This stage only: `snakemake --cores 2 sweeps`.
rule sweeps:
    input:
        SWEEP_TARGETS,
    localrule: True


ALL_TARGETS.extend(SWEEP_TARGETS)
