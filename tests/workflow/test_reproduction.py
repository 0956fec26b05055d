"""The record reproduces on another machine. Every workflow job runs OpenBLAS's routines for
one processor family (``RECORD_BLAS_CORETYPE``, workflow/rules/reproducibility.smk), so that
another x86-64 processor makes the same record bit for bit; where that pin does not hold
(another architecture, another OpenBLAS), the reproduction check's tolerances apply. Both are
held here on a few stages of the coarse run (the targets of tests/data/coarse_record/
emulation.json, written by tools/coarse_record.py): made again with another family in the
environment, the record is identical (the pin holds); made with another family forced past the
pin (``IMPACTDAMPER_OPENBLAS_CORETYPE``: another machine emulated), it reproduces the committed
coarse record within the stated tolerances (reporting/record_tolerances.py and the coarse
record's tolerances.json). About 2 min each on two cores.

The quick tests hold the README's paragraph and the report's macros to the measured record."""

import json
import os
import re
import importlib.util
from pathlib import Path

import pytest

from impactdamper.reporting.record_tolerances import (
    BLAS_CORETYPE_OVERRIDE,
    DEFAULT,
    tolerance_of,
)
from impactdamper.reporting.recordcheck import check_record, reproducibility_macros

ROOT = Path(__file__).resolve().parents[2]
RECORD = ROOT / "tests" / "data" / "coarse_record"
EMULATION = json.loads((RECORD / "emulation.json").read_text())
OUTPUT_ROOT = "results/ci_emulated"
# The family CI forces past the pin (another machine), and one the pin overrides.
FAMILY = "Sandybridge"
OVERRIDDEN = "Nehalem"

# tools/ is not a package: the script is loaded by its path (no sys.path change).
_SPEC = importlib.util.spec_from_file_location("coarse_record", ROOT / "tools" / "coarse_record.py")
coarse_record = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(coarse_record)
openblas_cores, regenerate = coarse_record.openblas_cores, coarse_record.regenerate


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
        assert run["openblas"] == [family], (family, run["openblas"])
        assert run["reproduces"] and run["failed"] == 0, run["summary"]
        assert run["identical"] < run["files"], "the emulated machine changed nothing: the emulation did not take"


def test_the_pin_held_against_another_family_in_the_environment():
    pinned = EMULATION["pinned"]
    assert pinned["reproduces"] and pinned["identical"] == pinned["files"] >= len(EMULATION["targets"]), pinned


def test_the_readme_quotes_the_emulation():
    readme = (ROOT / "README.md").read_text()
    paragraph = " ".join(readme.split("### Reproducing the record on another machine")[1].split("\n#")[0].split())
    runs = EMULATION["runs"].values()
    low, high = min(r["sensitive"] for r in runs), max(r["sensitive"] for r in runs)
    points = max(r["points"] for r in runs)
    assert f"{low} to {high} of {points:,} labelled points" in paragraph, paragraph
    assert "python -m impactdamper check-record" in paragraph
    pinned = EMULATION["pinned"]
    assert f"{pinned['identical']} files identical" in paragraph and pinned["identical"] == pinned["files"]
    # The tolerances it quotes are the table's.
    assert f"relative {DEFAULT.rtol:.0e}".replace("e-0", "e-") in paragraph
    assert f"within {DEFAULT.cells} cells" in paragraph
    assert f"at most {100 * tolerance_of('figures/sweep_gap.csv').max_sensitive:g} % of a sweep" in paragraph
    assert f"{100 * tolerance_of('figures/map_theta.csv').max_sensitive:g} % of a regime map" in paragraph


def test_the_report_macros_render_the_emulation():
    tex = reproducibility_macros(EMULATION).tex()
    runs = EMULATION["runs"].values()
    assert re.search(r"\\newcommand\{\\ReproSensitiveMax\}\{(\d+)\}", tex).group(1) == str(
        max(r["sensitive"] for r in runs)
    )
    assert "\\newcommand{\\ReproFamilies}{" + " and ".join(EMULATION["runs"]) + "}" in tex


def _regenerated(env: dict):
    """The targets made again with ``env`` over this process's environment (no override of the
    pin unless ``env`` names one), checked against the committed coarse record."""
    base = {k: v for k, v in os.environ.items() if k != BLAS_CORETYPE_OVERRIDE}
    root = regenerate(OUTPUT_ROOT, {**base, "PYTHONPATH": str(ROOT / "src"), **env}, EMULATION["targets"])
    verdicts = check_record(root, str(RECORD), ROOT)
    assert {v.path for v in verdicts} >= set(EMULATION["targets"])
    return verdicts


@pytest.mark.slow
def test_the_coarse_stages_reproduce_under_another_kernel_family():
    env = {BLAS_CORETYPE_OVERRIDE: FAMILY, "OPENBLAS_CORETYPE": FAMILY}
    assert openblas_cores({**os.environ, **env}) == [FAMILY], "OpenBLAS did not load the emulated family"
    failed = [v.line() for v in _regenerated(env) if v.status == "fail"]
    assert not failed, "\n".join(failed)


@pytest.mark.slow
def test_the_coarse_stages_are_identical_whatever_family_the_environment_names():
    assert openblas_cores({**os.environ, "OPENBLAS_CORETYPE": OVERRIDDEN}) == [OVERRIDDEN]
    changed = [v.line() for v in _regenerated({"OPENBLAS_CORETYPE": OVERRIDDEN}) if v.detail != "identical"]
    assert not changed, "\n".join(changed)
