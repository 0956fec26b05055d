# Reproducibility: the report's numbers on how the record reproduces on another machine. The
# committed coarse record and what emulated machines gave against it are made by
# tools/coarse_record.py (not by the workflow: it runs the workflow three times); this rule
# renders them with the reproduction check's tolerances (reporting/recordcheck.py) as macros.
# The record is read from the repository itself (an absolute path), whatever the output root.


rule reproducibility_macros:
    input:
        script="workflow/scripts/reproducibility_macros.py",
        library=library(REPORTING),
        emulation=str(Path(workflow.basedir) / "tests" / "data" / "coarse_record" / "emulation.json"),
    output:
        macros="paper/generated/reproducibility_macros.tex",
    log:
        "logs/report/reproducibility_macros.log",
    benchmark:
        benchmark_file("reproducibility_macros")
    conda:
        ENV
    script:
        "../scripts/reproducibility_macros.py"


ALL_TARGETS.append("paper/generated/reproducibility_macros.tex")
