# The report: paper/report.tex compiled by latexmk into paper/report.pdf. Included last, so
# that every figure and generated LaTeX file of the other stages is an input; notebooks are
# not (they never produce a number the report depends on).
REPORT_SOURCES = ["paper/report.tex", "paper/references.tex", "paper/latexmkrc"] + sorted(
    str(p) for p in Path("paper/sections").glob("*.tex")
)
REPORT_INPUTS = [t for t in ALL_TARGETS if t.startswith(("figures/", "paper/generated/"))]


rule report:
    input:
        REPORT_SOURCES,
        REPORT_INPUTS,
    output:
        "paper/report.pdf",
    log:
        "logs/report.log",
    conda:
        ENV
    shell:
        # Fixed dates (SOURCE_DATE_EPOCH) and no trailer id (preamble) make the PDF
        # byte-identical from run to run. A fresh build/ each time: with the fixed dates
        # latexmk took an edited section for up to date and kept the old PDF.
        "cd paper && rm -rf build && SOURCE_DATE_EPOCH=0 FORCE_SOURCE_DATE=1 "
        "latexmk -r latexmkrc -outdir=build report.tex > ../{log} 2>&1 "
        "&& cp build/report.pdf report.pdf"


ALL_TARGETS.append("paper/report.pdf")


rule readme_summary:
    input:
        script="workflow/scripts/readme_summary.py",
        library=library(REPORTING),
        # The report stages' records, in this order (a later stage's macro of the same name wins).
        records=[
            "results/report/verdict.json",
            "results/report/orbits.json",
            "results/report/performance.json",
            "results/report/sweeps.json",
            "results/report/design.json",
            "results/report/claims.json",
        ],
        stated="figures/impacts_stated.csv",
        located="figures/impacts_located.csv",
    output:
        "figures/readme_summary.md",
    log:
        "logs/readme_summary.log",
    conda:
        ENV
    script:
        "../scripts/readme_summary.py"


ALL_TARGETS.append("figures/readme_summary.md")
