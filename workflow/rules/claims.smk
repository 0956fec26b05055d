# Stage: the paper's Fig. 2 claims searched beyond the gap. At the stated Delta0/x_st each of
# theta, mu, N, delta1, delta2 and R is varied alone (one job per parameter, wildcard
# `parameter`), the intervals where claim (a), claim (b) and both hold are located and
# gathered; a two-parameter map (config claims_search.map) runs as chunks of rows. The verdict
# (reference.smk) reads the gathered intervals.
# Convention: every script runs through `script:` and has a main() the tests call directly.

CLAIMS_PARAMETERS = ["theta", "mu", "N", "delta1", "delta2", "R"]


rule claims_parameter:
    input:
        script="workflow/scripts/claims_parameter.py",
        library=library(BASELINES, study("claims", "config", "replication"), REPORTING),
    output:
        json="results/claims/{parameter}.json",
    wildcard_constraints:
        parameter="|".join(CLAIMS_PARAMETERS),
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    log:
        "logs/claims/{parameter}.log",
    conda:
        ENV
    script:
        "../scripts/claims_parameter.py"


rule claims_by_parameter:
    input:
        script="workflow/scripts/claims_gather.py",
        library=library(BASELINES, study("claims", "config", "replication"), REPORTING),
        results=expand("results/claims/{parameter}.json", parameter=CLAIMS_PARAMETERS),
    output:
        csv="figures/claims_by_parameter.csv",
        json="figures/claims_by_parameter_settings.json",
        grid="figures/claims_by_parameter_grid.csv",
        tex="paper/generated/claims_table.tex",
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    log:
        "logs/claims/claims_by_parameter.log",
    conda:
        ENV
    script:
        "../scripts/claims_gather.py"


rule claims_map_chunk:
    input:
        script="workflow/scripts/claims_map_chunk.py",
        library=library(BASELINES, study("claims", "config", "replication"), REPORTING),
    output:
        csv="results/claims/map_{chunk}.csv",
    wildcard_constraints:
        chunk=r"\d+",
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    log:
        "logs/claims/map_{chunk}.log",
    conda:
        ENV
    script:
        "../scripts/claims_map_chunk.py"


rule claims_map:
    input:
        script="workflow/scripts/claims_map_gather.py",
        library=library(BASELINES, study("claims", "config", "replication"), REPORTING),
        chunks=claims_map_chunk_files,
    output:
        csv="figures/claims_map.csv",
        json="figures/claims_map_settings.json",
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    log:
        "logs/claims/claims_map.log",
    conda:
        ENV
    script:
        "../scripts/claims_map_gather.py"


rule fig_claims_by_parameter:
    input:
        script="workflow/scripts/fig_claims_by_parameter.py",
        library=library(REPORTING),
        style=STYLE,
        csv="figures/claims_by_parameter.csv",
        json="figures/claims_by_parameter_settings.json",
    output:
        pdf="figures/claims_by_parameter.pdf",
        png="figures/claims_by_parameter.png",
    log:
        "logs/claims/fig_claims_by_parameter.log",
    conda:
        ENV
    script:
        "../scripts/fig_claims_by_parameter.py"


rule fig_claims_map:
    input:
        script="workflow/scripts/fig_claims_map.py",
        library=library(REPORTING),
        style=STYLE,
        csv="figures/claims_map.csv",
        json="figures/claims_map_settings.json",
        located="figures/located_case.json",
    output:
        pdf="figures/claims_map.pdf",
        png="figures/claims_map.png",
    log:
        "logs/claims/fig_claims_map.log",
    conda:
        ENV
    script:
        "../scripts/fig_claims_map.py"


ALL_TARGETS.extend(
    [
        "figures/claims_by_parameter.pdf",
        "figures/claims_by_parameter.png",
        "figures/claims_map.pdf",
        "figures/claims_map.png",
        "paper/generated/claims_table.tex",
    ]
)


rule claims_nearest:
    input:
        script="workflow/scripts/claims_nearest.py",
        library=library(BASELINES, study("claims", "config", "replication", "nearest"), REPORTING),
    output:
        json="figures/claims_nearest.json",
        timing="results/benchmarks/claims_nearest_timing.json",
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        verdict=parameters_json("verdict"),
        search=parameters_json("claims_search"),
    log:
        "logs/claims/claims_nearest.log",
    conda:
        ENV
    script:
        "../scripts/claims_nearest.py"


ALL_TARGETS.append("figures/claims_nearest.json")
