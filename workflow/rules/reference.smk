# Stage: the paper's reference case: Fig. 2a, Fig. 2b, the impact-time table and the
# replication verdict, for the stated case (config: reference) and for the located case (where
# the behaviour the paper reports does occur, found by rule gap_scan).
# Convention: every script runs through `script:` and reads snakemake.input/output/params/log
# (so no `from __future__` import: Snakemake prepends its preamble); each also has a main()
# that the record test (tests/test_figures_record.py) calls directly.

REFERENCE_CASES = ["stated", "located"]


rule reference_case_stated:
    input:
        script="workflow/scripts/solve_case.py",
        library=library(study("config", "intervals", "replication/cases", "replication/claims"), REPORTING),
    output:
        json="figures/reference_stated.json",
        fig2a="figures/fig2a_stated.csv",
        fig2b="figures/fig2b_stated.csv",
    log:
        "logs/reference/case_stated.log",
    benchmark:
        benchmark_file("reference_case_stated")
    conda:
        ENV
    params:
        case="stated",
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
    script:
        "../scripts/solve_case.py"


rule gap_scan:
    input:
        script="workflow/scripts/gap_scan.py",
        library=library(
            BASELINES,
            study(
                "config",
                "intervals",
                "replication/cases",
                "replication/claims",
                "replication/crosscheck",
                "replication/gapscan",
            ),
            REPORTING,
        ),
    output:
        csv="figures/gap_scan.csv",
        json="figures/located_case.json",
    log:
        "logs/reference/gap_scan.log",
    benchmark:
        benchmark_file("gap_scan")
    priority: 50
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        verdict=parameters_json("verdict"),
    script:
        "../scripts/gap_scan.py"


rule reference_case_located:
    input:
        script="workflow/scripts/solve_case.py",
        library=library(study("config", "intervals", "replication/cases", "replication/claims"), REPORTING),
        located="figures/located_case.json",
    output:
        json="figures/reference_located.json",
        fig2a="figures/fig2a_located.csv",
        fig2b="figures/fig2b_located.csv",
    log:
        "logs/reference/case_located.log",
    benchmark:
        benchmark_file("reference_case_located")
    conda:
        ENV
    params:
        case="located",
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
    script:
        "../scripts/solve_case.py"


rule fig2a:
    input:
        script="workflow/scripts/fig2a.py",
        style=STYLE,
        library=library(study("vocabulary"), REPORTING),
        csv="figures/fig2a_{case}.csv",
        json="figures/reference_{case}.json",
    output:
        pdf="figures/fig2a_{case}.pdf",
        png="figures/fig2a_{case}.png",
    log:
        "logs/reference/fig2a_{case}.log",
    benchmark:
        benchmark_file("fig2a", "case")
    wildcard_constraints:
        case="stated|located",
    conda:
        ENV
    script:
        "../scripts/fig2a.py"


rule fig2b:
    input:
        script="workflow/scripts/fig2b.py",
        style=STYLE,
        library=library(study("vocabulary"), REPORTING),
        csv="figures/fig2b_{case}.csv",
        json="figures/reference_{case}.json",
    output:
        pdf="figures/fig2b_{case}.pdf",
        png="figures/fig2b_{case}.png",
    log:
        "logs/reference/fig2b_{case}.log",
    benchmark:
        benchmark_file("fig2b", "case")
    wildcard_constraints:
        case="stated|located",
    conda:
        ENV
    script:
        "../scripts/fig2b.py"


rule impact_table:
    input:
        script="workflow/scripts/impact_table.py",
        library=library(REPORTING),
        json="figures/reference_{case}.json",
    output:
        csv="figures/impacts_{case}.csv",
        tex="paper/generated/impacts_{case}.tex",
    log:
        "logs/reference/impact_table_{case}.log",
    benchmark:
        benchmark_file("impact_table", "case")
    wildcard_constraints:
        case="stated|located",
    conda:
        ENV
    script:
        "../scripts/impact_table.py"


rule crosscheck_case:
    input:
        script="workflow/scripts/crosscheck_case.py",
        library=library(
            BASELINES,
            study("config", "intervals", "replication/cases", "replication/claims", "replication/crosscheck"),
            REPORTING,
        ),
        json="figures/reference_{case}.json",
    output:
        json="figures/crosscheck_{case}.json",
    log:
        "logs/reference/crosscheck_{case}.log",
    benchmark:
        benchmark_file("crosscheck_case", "case")
    wildcard_constraints:
        case="stated|located",
    conda:
        ENV
    params:
        solver=parameters_json("solver"),
        verdict=parameters_json("verdict"),
    script:
        "../scripts/crosscheck_case.py"


rule other_readings:
    input:
        script="workflow/scripts/other_readings.py",
        library=library(
            BASELINES,
            study(
                "config",
                "intervals",
                "replication/cases",
                "replication/claims",
                "replication/crosscheck",
                "replication/readings",
            ),
            REPORTING,
        ),
    output:
        csv="figures/other_readings.csv",
        json="figures/other_readings.json",
    log:
        "logs/reference/other_readings.log",
    benchmark:
        benchmark_file("other_readings")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        verdict=parameters_json("verdict"),
    script:
        "../scripts/other_readings.py"


rule fig_located_range:
    input:
        script="workflow/scripts/fig_located_range.py",
        style=STYLE,
        library=library(study("vocabulary"), REPORTING),
        csv="figures/gap_scan.csv",
        json="figures/located_case.json",
    output:
        pdf="figures/located_range.pdf",
        png="figures/located_range.png",
    log:
        "logs/reference/fig_located_range.log",
    benchmark:
        benchmark_file("fig_located_range")
    conda:
        ENV
    script:
        "../scripts/fig_located_range.py"


rule verdict:
    input:
        script="workflow/scripts/verdict.py",
        library=library(
            study(
                "config",
                "intervals",
                "replication/cases",
                "replication/claims",
                "replication/record",
                "replication/verdict",
                "vocabulary",
            ),
            REPORTING,
        ),
        stated="figures/reference_stated.json",
        located="figures/reference_located.json",
        cc_stated="figures/crosscheck_stated.json",
        cc_located="figures/crosscheck_located.json",
        scan="figures/located_case.json",
        readings="figures/other_readings.json",
        claims="figures/claims_by_parameter_settings.json",
        claims_map="figures/claims_map.csv",
    output:
        json="figures/verdict.json",
        csv="figures/verdict.csv",
        record="results/report/verdict.json",
        tex="paper/generated/verdict_macros.tex",
    log:
        "logs/reference/verdict.log",
    benchmark:
        benchmark_file("verdict")
    conda:
        ENV
    script:
        "../scripts/verdict.py"


REFERENCE_TARGETS = (
    expand("figures/fig2{panel}_{case}.{ext}", panel=["a", "b"], case=REFERENCE_CASES, ext=["pdf", "png"])
    + expand("figures/impacts_{case}.csv", case=REFERENCE_CASES)
    + expand("paper/generated/impacts_{case}.tex", case=REFERENCE_CASES)
    + ["figures/located_range.pdf", "figures/located_range.png"]
    + ["figures/verdict.json", "figures/verdict.csv", "paper/generated/verdict_macros.tex"]
)
ALL_TARGETS.extend(REFERENCE_TARGETS)


# This stage alone: `snakemake --cores 2 reference`.
rule reference:
    input:
        REFERENCE_TARGETS,
    localrule: True
