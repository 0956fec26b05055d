# The guided-tour notebooks in notebooks/ (jupytext percent format; the .py files
# are the source). Each rule executes one notebook end to end in a Jupyter kernel, so a
# broken notebook fails the build. The executed copies in results/notebooks/ are not a
# record: the report reads no number from them.
#
# `jupytext --execute` runs the notebook with nbconvert in the kernel its header names
# (python3): tools/setup.sh registers it with `python3 -m ipykernel install --user`.


rule notebook_reference_case:
    input:
        notebook="notebooks/01_reference_case.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
    output:
        "results/notebooks/01_reference_case.ipynb",
    log:
        "logs/notebooks/01_reference_case.log",
    benchmark:
        benchmark_file("notebook_reference_case")
    conda:
        ENV
    shell:
        "jupytext --to ipynb --execute {input.notebook} --output {output} > {log} 2>&1"


rule notebook_gap_sweep:
    input:
        notebook="notebooks/02_gap_sweep.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
    output:
        "results/notebooks/02_gap_sweep.ipynb",
    log:
        "logs/notebooks/02_gap_sweep.log",
    benchmark:
        benchmark_file("notebook_gap_sweep")
    conda:
        ENV
    shell:
        "jupytext --to ipynb --execute {input.notebook} --output {output} > {log} 2>&1"


rule notebook_your_own_damper:
    input:
        notebook="notebooks/03_your_own_damper.py",
        library=library(study("vocabulary"), REPORTING),
        style=STYLE,
    output:
        "results/notebooks/03_your_own_damper.ipynb",
    log:
        "logs/notebooks/03_your_own_damper.log",
    benchmark:
        benchmark_file("notebook_your_own_damper")
    conda:
        ENV
    shell:
        "jupytext --to ipynb --execute {input.notebook} --output {output} > {log} 2>&1"


rule notebook_choosing_a_suppressor:
    input:
        notebook="notebooks/04_choosing_a_suppressor.py",
        library=library(
            study(
                "design/design",
                "design/devices",
                "design/impact_searches",
                "design/optimum",
                "design/search_setup",
                "design/search",
                "design/subregions",
                "design/tasks",
                "design/tmd",
                "design/verdict",
                "vocabulary",
            ),
            REPORTING,
        ),
        style=STYLE,
        # the design table of the same object: the notebook shows it rather than searching again
        design="figures/design_optimum.json",
    output:
        "results/notebooks/04_choosing_a_suppressor.ipynb",
    log:
        "logs/notebooks/04_choosing_a_suppressor.log",
    benchmark:
        benchmark_file("notebook_choosing_a_suppressor")
    conda:
        ENV
    shell:
        'IMPACTDAMPER_DESIGN_RECORD="$PWD/{input.design}" '
        "jupytext --to ipynb --execute {input.notebook} --output {output} > {log} 2>&1"


ALL_TARGETS.extend(
    [
        "results/notebooks/01_reference_case.ipynb",
        "results/notebooks/02_gap_sweep.ipynb",
        "results/notebooks/03_your_own_damper.ipynb",
        "results/notebooks/04_choosing_a_suppressor.ipynb",
    ]
)
