# Stage: the paper's Fig. 2 claims searched beyond the gap. At the stated Delta0/x_st each of
# theta, mu, N, delta1, delta2 and R is varied alone (one job per parameter, wildcard
# `parameter`), the intervals where claim (a), claim (b) and both hold are located and
# gathered; a two-parameter map (config claims_search.map) runs as chunks of rows. The verdict
# (reference.smk) reads the gathered intervals.
# Convention: every script runs through `script:` and has a main() the tests call directly.

from impactdamper.studies.claims.search import SEARCH_PARAMETERS

# One job per searched parameter (every relative parameter but the gap, from the parameter table).
CLAIMS_PARAMETERS = list(SEARCH_PARAMETERS)


rule claims_parameter:
    input:
        script="workflow/scripts/claims_parameter.py",
        library=library(
            study("claims/search", "config", "intervals", "replication/cases", "replication/claims"),
            REPORTING,
        ),
    output:
        json="results/claims/{parameter}.json",
    log:
        "logs/claims/{parameter}.log",
    benchmark:
        benchmark_file("claims_parameter", "parameter")
    wildcard_constraints:
        parameter="|".join(CLAIMS_PARAMETERS),
    priority: 40
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    script:
        "../scripts/claims_parameter.py"


rule claims_by_parameter:
    input:
        script="workflow/scripts/claims_gather.py",
        library=library(
            BASELINES,
            study(
                "claims/claims_evaluator",
                "claims/record",
                "claims/search",
                "config",
                "intervals",
                "replication/cases",
                "replication/claims",
                "replication/crosscheck",
                "replication/gapscan",
                "vocabulary",
            ),
            REPORTING,
        ),
        results=expand("results/claims/{parameter}.json", parameter=CLAIMS_PARAMETERS),
    output:
        csv="figures/claims_by_parameter.csv",
        json="figures/claims_by_parameter_settings.json",
        grid="figures/claims_by_parameter_grid.csv",
        tex="paper/generated/claims_table.tex",
    log:
        "logs/claims/claims_by_parameter.log",
    benchmark:
        benchmark_file("claims_by_parameter")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    script:
        "../scripts/claims_gather.py"


# A claims map: the grid computed where its cells change, then refined beyond it. One core per
# job (the batch's workers = threads): on two processes a map used 1.5 of two cores and, as a
# two-core job, waited for every one-core job and ran alone; one process each, they pack in pairs.
rule claims_map:
    input:
        script="workflow/scripts/claims_map.py",
        library=library(
            study("claims/maps", "config", "intervals", "replication/cases", "replication/claims"),
            REPORTING,
        ),
    output:
        csv="figures/claims_map.csv",
        json="figures/claims_map_settings.json",
        refined="figures/claims_map_refined.csv",
    log:
        "logs/claims/claims_map.log",
    benchmark:
        benchmark_file("claims_map")
    priority: 40
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    script:
        "../scripts/claims_map.py"


CLAIMS_PAIR_MAPS = list(config["claims_search"]["pair_maps"])


rule claims_pair_map:
    input:
        script="workflow/scripts/claims_map.py",
        library=library(
            study("claims/maps", "config", "intervals", "replication/cases", "replication/claims"),
            REPORTING,
        ),
    output:
        csv="figures/claims_map_{name}.csv",
        json="figures/claims_map_{name}_settings.json",
        refined="figures/claims_map_{name}_refined.csv",
    log:
        "logs/claims/claims_map_{name}.log",
    benchmark:
        benchmark_file("claims_pair_map", "name")
    wildcard_constraints:
        name="|".join(CLAIMS_PAIR_MAPS),
    priority: 40
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        search=parameters_json("claims_search"),
    script:
        "../scripts/claims_map.py"


rule fig_claims_maps:
    input:
        script="workflow/scripts/fig_claims_maps.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        csv=["figures/claims_map.csv"] + expand("figures/claims_map_{name}.csv", name=CLAIMS_PAIR_MAPS),
        json=["figures/claims_map_settings.json"]
        + expand("figures/claims_map_{name}_settings.json", name=CLAIMS_PAIR_MAPS),
        refined=["figures/claims_map_refined.csv"]
        + expand("figures/claims_map_{name}_refined.csv", name=CLAIMS_PAIR_MAPS),
        located="figures/located_case.json",
    output:
        pdf="figures/claims_maps.pdf",
        png="figures/claims_maps.png",
    log:
        "logs/claims/fig_claims_maps.log",
    benchmark:
        benchmark_file("fig_claims_maps")
    conda:
        ENV
    script:
        "../scripts/fig_claims_maps.py"


rule fig_claims_by_parameter:
    input:
        script="workflow/scripts/fig_claims_by_parameter.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        csv="figures/claims_by_parameter.csv",
        json="figures/claims_by_parameter_settings.json",
    output:
        pdf="figures/claims_by_parameter.pdf",
        png="figures/claims_by_parameter.png",
    log:
        "logs/claims/fig_claims_by_parameter.log",
    benchmark:
        benchmark_file("fig_claims_by_parameter")
    conda:
        ENV
    script:
        "../scripts/fig_claims_by_parameter.py"


rule fig_claims_map:
    input:
        script="workflow/scripts/fig_claims_map.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        csv="figures/claims_map.csv",
        json="figures/claims_map_settings.json",
        refined="figures/claims_map_refined.csv",
        located="figures/located_case.json",
    output:
        pdf="figures/claims_map.pdf",
        png="figures/claims_map.png",
    log:
        "logs/claims/fig_claims_map.log",
    benchmark:
        benchmark_file("fig_claims_map")
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
        "figures/claims_maps.pdf",
        "figures/claims_maps.png",
    ]
)


rule claims_nearest:
    input:
        script="workflow/scripts/claims_nearest.py",
        library=library(
            BASELINES,
            study(
                "claims/answer_check",
                "claims/claims_evaluator",
                "claims/nearest",
                "claims/round_changes",
                "config",
                "intervals",
                "replication/cases",
                "replication/claims",
                "replication/crosscheck",
                "vocabulary",
            ),
            REPORTING,
        ),
    output:
        json="figures/claims_nearest.json",
        timing="results/benchmarks/claims_nearest_timing.json",
    log:
        "logs/claims/claims_nearest.log",
    benchmark:
        benchmark_file("claims_nearest")
    priority: 40
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        verdict=parameters_json("verdict"),
        search=parameters_json("claims_search"),
    script:
        "../scripts/claims_nearest.py"


ALL_TARGETS.append("figures/claims_nearest.json")


rule claims_macros:
    input:
        script="workflow/scripts/claims_macros.py",
        library=library(
            BASELINES,
            study(
                "claims/claims_evaluator",
                "claims/record",
                "claims/search",
                "config",
                "intervals",
                "replication/cases",
                "replication/claims",
                "replication/crosscheck",
                "replication/gapscan",
                "vocabulary",
            ),
            REPORTING,
        ),
        nearest="figures/claims_nearest.json",
        search="figures/claims_by_parameter_settings.json",
        maps=["figures/claims_map.csv"] + expand("figures/claims_map_{name}.csv", name=CLAIMS_PAIR_MAPS),
        map_settings=["figures/claims_map_settings.json"]
        + expand("figures/claims_map_{name}_settings.json", name=CLAIMS_PAIR_MAPS),
        located="figures/located_case.json",
    output:
        record="results/report/claims.json",
        tex="paper/generated/claims_macros.tex",
    log:
        "logs/claims/claims_macros.log",
    benchmark:
        benchmark_file("claims_macros")
    conda:
        ENV
    params:
        pair_maps=CLAIMS_PAIR_MAPS,
    script:
        "../scripts/claims_macros.py"


ALL_TARGETS.append("paper/generated/claims_macros.tex")
