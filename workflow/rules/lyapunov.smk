# Stage: Lyapunov exponents of the impacting flow (exact tangent map). The largest exponent
# along the gap sweep (each point of the sweeps stage's table run again from its start state,
# both directions; the np points labelled), over the theta map's plane on a grid of its own
# (config: lyapunov.map; its np cells labelled after the Newton rescue), the checks that do not
# use the tangent walk (Floquet multipliers, Benettin, the sum rule, the two backends: consistency
# checks, sharing its flow or events) and the independent one (Benettin on solve_ivp), the
# benchmark, the stage's record and its figures. The sweep's rows and the map's rows run as
# chunks, one job each (lyapunov.sweep_chunks, lyapunov.map.chunks), gathered afterwards.
# Convention: every script runs through `script:` and has a main() the tests call directly.


# The chunks of the sweep's and the map's exponents.
LYAPUNOV_SWEEP_CHUNKS = range(config["lyapunov"]["sweep_chunks"])
LYAPUNOV_MAP_CHUNKS = range(config["lyapunov"]["map"]["chunks"])


rule lyapunov_sweep_chunk:
    input:
        script="workflow/scripts/lyapunov_sweep.py",
        library=library(study("config", "lyapunov/sweep"), REPORTING),
        sweep="figures/sweep_gap.csv",
    output:
        csv="results/lyapunov/sweep_{chunk}.csv",
        json="results/benchmarks/lyapunov/sweep_{chunk}.json",
    log:
        "logs/lyapunov/sweep_{chunk}.log",
    benchmark:
        benchmark_file("lyapunov_sweep_chunk", "chunk")
    wildcard_constraints:
        chunk=r"\d+",
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        lyapunov=parameters_json("lyapunov"),
    script:
        "../scripts/lyapunov_sweep.py"


rule lyapunov_sweep:
    input:
        script="workflow/scripts/gather_csv.py",
        library=library(REPORTING),
        chunks=expand("results/lyapunov/sweep_{chunk}.csv", chunk=LYAPUNOV_SWEEP_CHUNKS),
    output:
        csv="figures/lyapunov_sweep.csv",
    log:
        "logs/lyapunov/sweep_gather.log",
    benchmark:
        benchmark_file("lyapunov_sweep")
    conda:
        ENV
    script:
        "../scripts/gather_csv.py"


rule lyapunov_map_chunk:
    input:
        script="workflow/scripts/lyapunov_map.py",
        library=library(study("config", "lyapunov/exponent_map", "lyapunov/sweep"), REPORTING),
    output:
        csv="results/lyapunov/map_{chunk}.csv",
        json="results/benchmarks/lyapunov/map_{chunk}.json",
    log:
        "logs/lyapunov/map_{chunk}.log",
    benchmark:
        benchmark_file("lyapunov_map_chunk", "chunk")
    wildcard_constraints:
        chunk=r"\d+",
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        lyapunov=parameters_json("lyapunov"),
    script:
        "../scripts/lyapunov_map.py"


rule lyapunov_map:
    input:
        script="workflow/scripts/gather_csv.py",
        library=library(REPORTING),
        chunks=expand("results/lyapunov/map_{chunk}.csv", chunk=LYAPUNOV_MAP_CHUNKS),
    output:
        csv="figures/lyapunov_map.csv",
    log:
        "logs/lyapunov/map_gather.log",
    benchmark:
        benchmark_file("lyapunov_map")
    conda:
        ENV
    script:
        "../scripts/gather_csv.py"


rule lyapunov_checks:
    input:
        script="workflow/scripts/lyapunov_checks.py",
        library=library(study("config", "lyapunov/checks"), REPORTING),
        sweep="figures/sweep_gap.csv",
    output:
        json="figures/lyapunov_checks.json",
    log:
        "logs/lyapunov/checks.log",
    benchmark:
        benchmark_file("lyapunov_checks")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        lyapunov=parameters_json("lyapunov"),
    script:
        "../scripts/lyapunov_checks.py"


rule lyapunov_independent:
    input:
        script="workflow/scripts/lyapunov_independent.py",
        library=library(
            study("config", "lyapunov/independent"),
            library_files("baselines/__init__") + library_files("baselines/benettin_ivp"),
            REPORTING,
        ),
    output:
        json="figures/lyapunov_independent.json",
        cpu="results/benchmarks/lyapunov_independent_cpu.json",
    log:
        "logs/lyapunov/independent.log",
    benchmark:
        benchmark_file("lyapunov_independent")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        lyapunov=parameters_json("lyapunov"),
    script:
        "../scripts/lyapunov_independent.py"


rule lyapunov_speed:
    input:
        script="workflow/scripts/lyapunov_speed.py",
        library=library(study("lyapunov/checks"), REPORTING),
    output:
        json="results/benchmarks/lyapunov_speed.json",
    log:
        "logs/lyapunov/speed.log",
    benchmark:
        benchmark_file("lyapunov_speed")
    conda:
        ENV
    params:
        lyapunov=parameters_json("lyapunov"),
    script:
        "../scripts/lyapunov_speed.py"


rule lyapunov_report:
    input:
        script="workflow/scripts/lyapunov_report.py",
        library=library(study("lyapunov/record", "vocabulary"), REPORTING),
        sweep="figures/lyapunov_sweep.csv",
        map="figures/lyapunov_map.csv",
        checks="figures/lyapunov_checks.json",
        independent="figures/lyapunov_independent.json",
        independent_cpu="results/benchmarks/lyapunov_independent_cpu.json",
        special="figures/orbit_special_points.csv",
        sweep_table="figures/sweep_gap.csv",
        speed="results/benchmarks/lyapunov_speed.json",
        sweep_timings=expand("results/benchmarks/lyapunov/sweep_{chunk}.json", chunk=LYAPUNOV_SWEEP_CHUNKS),
        map_timings=expand("results/benchmarks/lyapunov/map_{chunk}.json", chunk=LYAPUNOV_MAP_CHUNKS),
    output:
        record="results/report/lyapunov.json",
        macros="paper/generated/lyapunov_macros.tex",
        table="paper/generated/lyapunov_benettin_table.tex",
        timing="paper/generated/lyapunov_timing.tex",
    log:
        "logs/lyapunov/report.log",
    benchmark:
        benchmark_file("lyapunov_report")
    conda:
        ENV
    params:
        lyapunov=parameters_json("lyapunov"),
    script:
        "../scripts/lyapunov_report.py"


rule fig_lyapunov_map:
    input:
        script="workflow/scripts/fig_lyapunov_map.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        map="figures/lyapunov_map.csv",
    output:
        pdf="figures/lyapunov_map.pdf",
        png="figures/lyapunov_map.png",
    log:
        "logs/lyapunov/fig_map.log",
    benchmark:
        benchmark_file("fig_lyapunov_map")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        lyapunov=parameters_json("lyapunov"),
    script:
        "../scripts/fig_lyapunov_map.py"


LYAPUNOV_TARGETS = [
    "figures/lyapunov_sweep.csv",
    "figures/lyapunov_map.pdf",
    "figures/lyapunov_map.png",
    "figures/lyapunov_checks.json",
    "figures/lyapunov_independent.json",
    "paper/generated/lyapunov_macros.tex",
    "paper/generated/lyapunov_benettin_table.tex",
    "paper/generated/lyapunov_timing.tex",
]


# This stage only: `snakemake --cores 2 lyapunov`.
rule lyapunov:
    input:
        LYAPUNOV_TARGETS,
        "figures/sweep_bifurcation.pdf",
    localrule: True


ALL_TARGETS.extend(LYAPUNOV_TARGETS)
