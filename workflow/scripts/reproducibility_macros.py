"""The report's section on reproducibility: the reproduction check's tolerances
(reporting/record_tolerances.py) and what the emulated machines gave against the committed coarse
record (tests/data/coarse_record/emulation.json, written by tools/coarse_record.py), as LaTeX
macros (no number is typed by hand).

Outputs ``paper/generated/reproducibility_macros.tex``.
"""

from pathlib import Path

from impactdamper.reporting.recordcheck import reproducibility_macros
from impactdamper.reporting.records import read_json, run_stage


def main(emulation_json, out_macros) -> None:
    Path(out_macros).parent.mkdir(parents=True, exist_ok=True)
    Path(out_macros).write_text(reproducibility_macros(read_json(emulation_json)).tex())


JOB = "input.emulation output.macros"

if __name__ == "__main__":
    run_stage(snakemake, main, JOB)  # noqa: F821 (injected by Snakemake's script: directive)
