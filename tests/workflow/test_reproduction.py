"""The record reproduces on another machine: a few stages of the coarse run (the targets of
tests/data/coarse_record/emulation.json, written by tools/coarse_record.py) made again under
another OpenBLAS kernel family (``OPENBLAS_CORETYPE``, what another CPU would run) and held to
the committed coarse record by the reproduction check, within its stated tolerances
(reporting/record_tolerances.py and the coarse record's tolerances.json). A change that makes a
result depend on the machine beyond them fails here. About 3 min on two cores.

The quick tests hold the README's paragraph and the report's macros to the measured record."""

import json
import os
import re
import sys
from pathlib import Path

import pytest

from impactdamper.reporting.record_tolerances import DEFAULT, tolerance_of
from impactdamper.reporting.recordcheck import check_record, reproducibility_macros

ROOT = Path(__file__).resolve().parents[2]
RECORD = ROOT / "tests" / "data" / "coarse_record"
EMULATION = json.loads((RECORD / "emulation.json").read_text())
OUTPUT_ROOT = "results/ci_emulated"
# The family CI runs: not the one the record was made with here (Haswell), nor this machine's own.
FAMILY = "Sandybridge"

sys.path.insert(0, str(ROOT / "tools"))
from coarse_record import openblas_cores, regenerate  # noqa: E402


def test_the_committed_coarse_record_holds_every_target_and_passes_against_itself():
    for target in EMULATION["targets"]:
        assert (RECORD / target).is_file(), target
    verdicts = check_record(RECORD, str(RECORD), ROOT)
    assert len(verdicts) >= len(EMULATION["targets"]) and {v.status for v in verdicts} == {"pass"}


def test_the_emulated_machines_reproduced_the_record_within_the_tolerances():
    """What tools/coarse_record.py measured (the README and the report quote it)."""
    runs = EMULATION["runs"]
    assert len(runs) >= 2
    for family, run in runs.items():
        assert family in run["openblas"] or family == "Prescott", (family, run["openblas"])
        assert run["reproduces"] and run["failed"] == 0, run["summary"]
        assert run["identical"] < run["files"], "the emulated machine changed nothing: the emulation did not take"


def test_the_readme_quotes_the_emulation():
    readme = (ROOT / "README.md").read_text()
    paragraph = readme.split("### Reproducing the record on another machine")[1].split("\n#")[0]
    runs = EMULATION["runs"].values()
    low, high = min(r["sensitive"] for r in runs), max(r["sensitive"] for r in runs)
    points = max(r["points"] for r in runs)
    assert f"{low} to {high} of {points:,} labelled points" in paragraph, paragraph
    assert "python -m impactdamper check-record" in paragraph
    # The tolerances it quotes are the table's.
    assert f"relative {DEFAULT.rtol:.0e}".replace("e-0", "e-") in paragraph
    assert f"within {DEFAULT.cells} cells" in paragraph
    assert f"at most {100 * tolerance_of('figures/sweep_gap.csv').max_sensitive:g} % of a sweep" in paragraph
    assert f"{100 * tolerance_of('figures/map_theta.csv').max_sensitive:g} %\nof a regime map" in paragraph


def test_the_report_macros_render_the_emulation():
    tex = reproducibility_macros(EMULATION).tex()
    runs = EMULATION["runs"].values()
    assert re.search(r"\\newcommand\{\\ReproSensitiveMax\}\{(\d+)\}", tex).group(1) == str(
        max(r["sensitive"] for r in runs)
    )
    assert "\\newcommand{\\ReproFamilies}{" + " and ".join(EMULATION["runs"]) + "}" in tex


@pytest.mark.slow
def test_the_coarse_stages_reproduce_under_another_kernel_family():
    env = {**os.environ, "OPENBLAS_CORETYPE": FAMILY, "PYTHONPATH": str(ROOT / "src")}
    assert openblas_cores(env) == [FAMILY], "OpenBLAS did not load the emulated family"
    root = regenerate(OUTPUT_ROOT, env, EMULATION["targets"])
    verdicts = check_record(root, str(RECORD), ROOT)
    failed = [v.line() for v in verdicts if v.status == "fail"]
    assert not failed, "\n".join(failed)
    assert {v.path for v in verdicts} >= set(EMULATION["targets"])
