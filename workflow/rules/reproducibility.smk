# Reproducibility: the report's numbers on how the record reproduces on another machine. The
# committed coarse record and what emulated machines gave against it are made by
# tools/coarse_record.py (not by the workflow: it runs the workflow three times); this rule
# renders them with the reproduction check's tolerances (reporting/recordcheck.py) as macros.
# The record is read from the repository itself (an absolute path), whatever the output root.
#
# One set of BLAS routines for the record on every x86-64 processor. numpy's and scipy's OpenBLAS
# choose their routines by processor, and the set-up of every point (the 4 x 4 state matrix's
# eigen-decomposition, inverse, forced response, Cholesky factor) goes through them: that was the
# whole difference between machines (tools/coarse_record.py: the same stages under other
# OPENBLAS_CORETYPE families moved 855-861 numbers and 9-11 labels, while the compiled kernels
# built for a generic CPU, NUMBA_CPU_NAME=generic, changed nothing). Every job therefore runs the
# routines that every x86-64 processor has (OpenBLAS's Prescott family), at no cost for 4 x 4
# matrices (packing 2,000 points and settling 40: the same times within 5 %). Elsewhere (another
# architecture, another OpenBLAS) the name is ignored and the reproduction check's tolerances
# apply; IMPACTDAMPER_OPENBLAS_CORETYPE chooses another family (the emulation of such a machine).
from impactdamper.reporting.record_tolerances import pin_record_blas

pin_record_blas()


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
