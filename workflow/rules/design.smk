# Stage: choosing a suppressor. The linear references (bare object, absorber without a stop,
# optimal tuned-mass damper) with the design search's check against Den Hartog's closed form; the
# design charts of the paper's suppressor over the gap and a second parameter (worst branches
# located, best gaps located); the design table (both devices optimised by one global search
# for every criterion, under every uncertainty, with strokes and loads: the call behind
# `python -m impactdamper design`); the located worst branch checked three ways; the frequency
# responses of the optimal devices; the design command's benchmark (config: design). Every
# motion is settled as the design command settles it (impactdamper.studies.design.devices).
# Every script's worker processes are its job's threads. The design table and the command's
# benchmark run on two (the design command's own two workers, whose wall time the report gives
# as the command's on a two-core machine), so each holds both cores: declared as one core, each
# ran a third process beside another job (the command at mu 0.02 took 83 s there, under a minute alone).
# Their priorities pass any two one-core jobs' together (Snakemake picks the jobs of the largest
# total priority that fit), so that they run right after the compiled solver's benchmark, when
# both cores are free: otherwise a two-core job waits until no one-core job is left. The charts
# run on one core (their values do not depend on the workers). The design table's job also checks
# every row's answer against its box's halves (and adopts a lower half's): its own record.


rule design_baselines:
    input:
        script="workflow/scripts/design_baselines.py",
        library=library(
            study(
                "design/design",
                "design/devices",
                "design/impact_searches",
                "design/optimum",
                "design/search_setup",
                "design/search",
                "design/subregions",
                "design/verdict",
                "design/tmd",
                "design/tasks",
            ),
            REPORTING,
        ),
    output:
        csv="figures/design_baselines.csv",
        json="figures/design_baselines.json",
    log:
        "logs/design/baselines.log",
    benchmark:
        benchmark_file("design_baselines")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        design=parameters_json("design"),
    script:
        "../scripts/design_baselines.py"


rule design_chart:
    input:
        script="workflow/scripts/design_chart.py",
        library=library(study("design/design", "design/devices"), REPORTING),
    output:
        csv="figures/design_chart.csv",
        json="figures/design_chart.json",
    log:
        "logs/design/chart.log",
    benchmark:
        benchmark_file("design_chart")
    priority: 60
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        design=parameters_json("design"),
    script:
        "../scripts/design_chart.py"


rule design_chart_2d:
    input:
        script="workflow/scripts/design_chart_2d.py",
        library=library(study("design/design", "design/devices"), REPORTING),
    output:
        csv="figures/design_chart_2d.csv",
        json="figures/design_chart_2d.json",
    log:
        "logs/design/chart_2d.log",
    benchmark:
        benchmark_file("design_chart_2d")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        design=parameters_json("design"),
    script:
        "../scripts/design_chart_2d.py"


rule design_optimum:
    input:
        script="workflow/scripts/design_optimum.py",
        library=library(
            study(
                "design/design",
                "design/devices",
                "design/impact_searches",
                "design/optimum",
                "design/search_setup",
                "design/search",
                "design/subregions",
                "design/verdict",
                "design/tmd",
                "design/tasks",
            ),
            REPORTING,
        ),
    output:
        json="figures/design_optimum.json",
        csv="figures/design_optimum.csv",
        subregions="figures/design_subregions.json",
    log:
        "logs/design/optimum.log",
    benchmark:
        benchmark_file("design_optimum")
    priority: 900
    conda:
        ENV
    threads: 2
    params:
        reference=parameters_json("reference"),
        design=parameters_json("design"),
    script:
        "../scripts/design_optimum.py"


rule design_checks:
    input:
        script="workflow/scripts/design_checks.py",
        library=library(
            study("design/checks", "design/design", "design/devices", "design/verdict"),
            BASELINES,
            REPORTING,
        ),
        optimum="figures/design_optimum.json",
    output:
        json="figures/design_checks.json",
    log:
        "logs/design/checks.log",
    benchmark:
        benchmark_file("design_checks")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        design=parameters_json("design"),
    script:
        "../scripts/design_checks.py"


rule design_benchmark:
    input:
        script="workflow/scripts/design_benchmark.py",
        library=library(
            study(
                "design/design",
                "design/devices",
                "design/impact_searches",
                "design/optimum",
                "design/search_setup",
                "design/search",
                "design/subregions",
                "design/verdict",
                "design/tmd",
                "design/tasks",
            ),
            REPORTING,
        ),
        cli=library_files("cli"),
        optimum="figures/design_optimum.json",
    output:
        json="figures/design_benchmark.json",
    log:
        "logs/design/benchmark.log",
    benchmark:
        benchmark_file("design_benchmark")
    priority: 800
    conda:
        ENV
    threads: 2
    params:
        reference=parameters_json("reference"),
        design=parameters_json("design"),
    script:
        "../scripts/design_benchmark.py"


rule design_response:
    input:
        script="workflow/scripts/design_response.py",
        library=library(study("design/design", "design/devices", "design/verdict"), REPORTING),
        chart="figures/design_chart.json",
        optimum="figures/design_optimum.json",
    output:
        csv="figures/design_response.csv",
        json="figures/design_response.json",
    log:
        "logs/design/response.log",
    benchmark:
        benchmark_file("design_response")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        design=parameters_json("design"),
    script:
        "../scripts/design_response.py"


rule design_report:
    input:
        script="workflow/scripts/design_report.py",
        library=library(
            study(
                "design/devices",
                "design/record",
                "design/record_rows",
                "design/record_summary",
                "design/record_tables",
                "design/abstract",
                "design/verdict",
                "vocabulary",
            ),
            REPORTING,
        ),
        baselines="figures/design_baselines.json",
        chart="figures/design_chart.json",
        chart2d="figures/design_chart_2d.json",
        response="figures/design_response.json",
        optimum="figures/design_optimum.json",
        checks="figures/design_checks.json",
        subregions="figures/design_subregions.json",
        benchmark="figures/design_benchmark.json",
    output:
        record="results/report/design.json",
        macros="paper/generated/design_macros.tex",
        table="paper/generated/design_second_table.tex",
        design_table="paper/generated/design_table.tex",
        loads_table="paper/generated/design_loads_table.tex",
        benchmark_table="paper/generated/design_benchmark_table.tex",
    log:
        "logs/design/report.log",
    benchmark:
        benchmark_file("design_report")
    conda:
        ENV
    script:
        "../scripts/design_report.py"


rule fig_design_response:
    input:
        script="workflow/scripts/fig_design_response.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        response="figures/design_response.csv",
        summary="figures/design_response.json",
        baselines="figures/design_baselines.csv",
        optimum="figures/design_optimum.json",
    output:
        pdf="figures/design_response.pdf",
        png="figures/design_response.png",
    log:
        "logs/design/fig_response.log",
    benchmark:
        benchmark_file("fig_design_response")
    conda:
        ENV
    script:
        "../scripts/fig_design_response.py"


rule fig_design_chart:
    input:
        script="workflow/scripts/fig_design_chart.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        chart="figures/design_chart.csv",
        best="figures/design_chart.json",
        baselines="figures/design_baselines.json",
        optimum="figures/design_optimum.json",
    output:
        pdf="figures/design_chart.pdf",
        png="figures/design_chart.png",
    log:
        "logs/design/fig_chart.log",
    benchmark:
        benchmark_file("fig_design_chart")
    conda:
        ENV
    script:
        "../scripts/fig_design_chart.py"


rule fig_design_chart_2d:
    input:
        script="workflow/scripts/fig_design_chart_2d.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
        chart="figures/design_chart_2d.csv",
        best="figures/design_chart_2d.json",
        baselines="figures/design_baselines.json",
    output:
        pdf="figures/design_chart_2d.pdf",
        png="figures/design_chart_2d.png",
    log:
        "logs/design/fig_chart_2d.log",
    benchmark:
        benchmark_file("fig_design_chart_2d")
    conda:
        ENV
    script:
        "../scripts/fig_design_chart_2d.py"


DESIGN_TARGETS = [
    "figures/design_baselines.csv",
    "figures/design_baselines.json",
    "figures/design_chart.csv",
    "figures/design_chart.json",
    "figures/design_chart_2d.csv",
    "figures/design_chart_2d.json",
    "figures/design_response.csv",
    "figures/design_response.json",
    "figures/design_optimum.json",
    "figures/design_optimum.csv",
    "figures/design_checks.json",
    "figures/design_subregions.json",
    "figures/design_benchmark.json",
    "figures/design_response.pdf",
    "figures/design_response.png",
    "figures/design_chart.pdf",
    "figures/design_chart.png",
    "figures/design_chart_2d.pdf",
    "figures/design_chart_2d.png",
    "paper/generated/design_macros.tex",
    "paper/generated/design_second_table.tex",
    "paper/generated/design_table.tex",
    "paper/generated/design_loads_table.tex",
    "paper/generated/design_benchmark_table.tex",
]
ALL_TARGETS.extend(DESIGN_TARGETS)
