# Stage: choosing a suppressor. Frequency responses (upward and downward theta sweeps), the
# linear references (bare object, absorber without a stop, optimal tuned-mass damper), and the
# design charts over the gap and a second parameter, and the design table: both devices optimised
# jointly with located peaks, worst cases under detuning, strokes and loads (config: design). The sweeps' caps are the
# sweep stage's (config: sweep), the solver's tolerances config: solver. The design parameters,
# the band and the gap grids come from the config through impactdamper.studies.design.


rule design_baselines:
    input:
        script="workflow/scripts/design_baselines.py",
        library=library(study("design/design"), REPORTING),
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
        library=library(study("config", "design/design"), REPORTING),
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
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
        design=parameters_json("design"),
    script:
        "../scripts/design_chart.py"


rule design_chart_2d:
    input:
        script="workflow/scripts/design_chart_2d.py",
        library=library(study("config", "design/design"), REPORTING),
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
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
        design=parameters_json("design"),
    script:
        "../scripts/design_chart_2d.py"


rule design_response:
    input:
        script="workflow/scripts/design_response.py",
        library=library(study("config", "design/design"), REPORTING),
        chart="figures/design_chart.json",
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
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
        design=parameters_json("design"),
    script:
        "../scripts/design_response.py"


rule design_optimum:
    input:
        script="workflow/scripts/design_optimum.py",
        library=library(study("config", "design/design", "design/optimum"), REPORTING),
        chart="figures/design_chart.json",
    output:
        json="figures/design_optimum.json",
        csv="figures/design_optimum.csv",
    log:
        "logs/design/optimum.log",
    benchmark:
        benchmark_file("design_optimum")
    priority: 60
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        sweep=parameters_json("sweep"),
        design=parameters_json("design"),
    script:
        "../scripts/design_optimum.py"


rule design_report:
    input:
        script="workflow/scripts/design_report.py",
        library=library(study("design/design", "design/optimum", "design/record", "vocabulary"), REPORTING),
        optimum="figures/design_optimum.json",
        baselines="figures/design_baselines.json",
        chart="figures/design_chart.json",
        chart2d="figures/design_chart_2d.json",
        response="figures/design_response.json",
        response_csv="figures/design_response.csv",
    output:
        record="results/report/design.json",
        macros="paper/generated/design_macros.tex",
        table="paper/generated/design_second_table.tex",
        design_table="paper/generated/design_table.tex",
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
        library=library(REPORTING),
        style=STYLE,
        chart="figures/design_chart.csv",
        best="figures/design_chart.json",
        baselines="figures/design_baselines.json",
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
    "figures/design_response.pdf",
    "figures/design_response.png",
    "figures/design_chart.pdf",
    "figures/design_chart.png",
    "figures/design_chart_2d.pdf",
    "figures/design_chart_2d.png",
    "paper/generated/design_macros.tex",
    "paper/generated/design_second_table.tex",
    "paper/generated/design_table.tex",
]
ALL_TARGETS.extend(DESIGN_TARGETS)
