# The workflow's own cost: every job's benchmark gathered (the jobs of the latest run) into the
# report's table of the costliest rules and the run's total. It takes every other stage's
# products, so that it runs after their jobs; the report and the README summary read it, so
# their cost cannot be in it.
WORKFLOW_COST_TARGETS = ["paper/generated/workflow_cost_table.tex", "paper/generated/workflow_cost_macros.tex"]
WORKFLOW_COST_EXCLUDED = ["workflow_cost", "provenance", "report", "readme_summary"]


rule workflow_cost:
    input:
        script="workflow/scripts/workflow_cost.py",
        library=library(BASELINES, study("performance/cost", "performance/methods", "performance/record"), REPORTING),
        stages=list(ALL_TARGETS),
    output:
        json="figures/workflow_cost.json",
        table=WORKFLOW_COST_TARGETS[0],
        macros=WORKFLOW_COST_TARGETS[1],
        record="results/report/workflow_cost.json",
        page="docs/WORKFLOW_COST.md",
    log:
        "logs/workflow_cost.log",
    benchmark:
        benchmark_file("workflow_cost")
    conda:
        ENV
    params:
        benchmarks=BENCHMARK_DIR,
        exclude=WORKFLOW_COST_EXCLUDED,
        cores=planned_cores(),
        top=10,
    script:
        "../scripts/workflow_cost.py"


ALL_TARGETS.extend(["figures/workflow_cost.json", "docs/WORKFLOW_COST.md", *WORKFLOW_COST_TARGETS])


# The report's appendix of provenance: every figure, table and file of numbers of the report ->
# the rule that writes it, its script and the committed records it reads, from the workflow's
# own rules (workflow_rules, read when the job is planned, after every rules file is parsed);
# and the report's author line and locator from CITATION.cff.
PROVENANCE_READS = [t for t in ALL_TARGETS if t.startswith("paper/generated/")]


rule provenance:
    input:
        script="workflow/scripts/provenance.py",
        library=library(REPORTING),
        report="paper/report.tex",
        sections=sorted(str(p) for p in Path("paper/sections").glob("*.tex")),
        generated=PROVENANCE_READS,
    output:
        table="paper/generated/provenance_table.tex",
        citation="paper/generated/citation_macros.tex",
    log:
        "logs/report/provenance.log",
    benchmark:
        benchmark_file("provenance")
    conda:
        ENV
    params:
        rules=workflow_rules,
        citation=citation_metadata,
    script:
        "../scripts/provenance.py"


ALL_TARGETS.extend(["paper/generated/provenance_table.tex", "paper/generated/citation_macros.tex"])


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
    benchmark:
        benchmark_file("report")
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
        library=library(study("vocabulary"), REPORTING),
        # The report stages' records, in this order (a later stage's macro of the same name wins).
        records=[
            "results/report/verdict.json",
            "results/report/orbits.json",
            "results/report/performance.json",
            "results/report/sweeps.json",
            "results/report/design.json",
            "results/report/claims.json",
        ],
    output:
        "figures/readme_summary.md",
    log:
        "logs/readme_summary.log",
    benchmark:
        benchmark_file("readme_summary")
    conda:
        ENV
    script:
        "../scripts/readme_summary.py"


ALL_TARGETS.append("figures/readme_summary.md")


# The repository's benchmark page: the package's software benchmarks against its own targets,
# from the performance stage's record (the report states speed and accuracy as results), and the
# design command's times from its benchmark.
rule benchmarks_doc:
    input:
        script="workflow/scripts/benchmarks_doc.py",
        library=library(REPORTING),
        records=["results/report/performance.json"],
        design="figures/design_benchmark.json",
    output:
        page="docs/BENCHMARKS.md",
    log:
        "logs/benchmarks_doc.log",
    benchmark:
        benchmark_file("benchmarks_doc")
    conda:
        ENV
    script:
        "../scripts/benchmarks_doc.py"


ALL_TARGETS.append("docs/BENCHMARKS.md")
