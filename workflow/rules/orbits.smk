# Stage: periodic orbits solved directly. The one-impact orbit (seeded by Algorithm
# No. 1), the 2T cycle with three impacts (the paper's Fig. 2b motion) and the 3T cycle with
# four impacts are followed in Delta0/x_st by pseudo-arclength continuation with their
# stability (Floquet multipliers from saltation matrices) and admissibility (config: orbits);
# then the figure, and the report's macros and table.
# Convention: every script runs through `script:` and has a main() the tests call directly.


rule orbit_branches:
    input:
        script="workflow/scripts/orbit_branches.py",
        library=library(study("config", "intervals", "sweeps/branches"), REPORTING),
        located="figures/located_case.json",
    output:
        branches="figures/orbit_branches.csv",
        special="figures/orbit_special_points.csv",
        summary="figures/orbit_summary.json",
    log:
        "logs/orbits/orbit_branches.log",
    benchmark:
        benchmark_file("orbit_branches")
    conda:
        ENV
    params:
        reference=parameters_json("reference"),
        solver=parameters_json("solver"),
        orbits=parameters_json("orbits"),
    script:
        "../scripts/orbit_branches.py"


rule fig_orbit_branches:
    input:
        script="workflow/scripts/fig_orbit_branches.py",
        style=STYLE,
        library=library(study("config", "intervals", "sweeps/branches", "vocabulary"), REPORTING),
        branches="figures/orbit_branches.csv",
        special="figures/orbit_special_points.csv",
        summary="figures/orbit_summary.json",
    output:
        pdf="figures/orbit_branches.pdf",
        png="figures/orbit_branches.png",
    log:
        "logs/orbits/fig_orbit_branches.log",
    benchmark:
        benchmark_file("fig_orbit_branches")
    conda:
        ENV
    script:
        "../scripts/fig_orbit_branches.py"


rule orbit_report:
    input:
        script="workflow/scripts/orbit_report.py",
        library=library(study("config", "intervals", "sweeps/branches", "sweeps/orbit_record", "vocabulary"), REPORTING),
        branches="figures/orbit_branches.csv",
        special="figures/orbit_special_points.csv",
        summary="figures/orbit_summary.json",
    output:
        record="results/report/orbits.json",
        macros="paper/generated/orbit_macros.tex",
        table="paper/generated/orbit_special_points_table.tex",
    log:
        "logs/orbits/orbit_report.log",
    benchmark:
        benchmark_file("orbit_report")
    conda:
        ENV
    script:
        "../scripts/orbit_report.py"


ORBIT_TARGETS = [
    "figures/orbit_branches.csv",
    "figures/orbit_special_points.csv",
    "figures/orbit_summary.json",
    "figures/orbit_branches.pdf",
    "figures/orbit_branches.png",
    "paper/generated/orbit_macros.tex",
    "paper/generated/orbit_special_points_table.tex",
]
ALL_TARGETS.extend(ORBIT_TARGETS)


# This stage alone: `snakemake --cores 1 orbits`.
rule orbits:
    input:
        ORBIT_TARGETS,
    localrule: True
