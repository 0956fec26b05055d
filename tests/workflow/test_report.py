"""The report builds: latexmk compiles paper/report.tex from the committed figures and
generated files with no LaTeX error, no undefined reference or citation, and no overfull box,
into a PDF whose bytes do not depend on the time of the build."""

import hashlib
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def build(tmp: Path) -> tuple[Path, str]:
    shutil.copytree(ROOT / "paper", tmp / "paper", ignore=shutil.ignore_patterns("build", "report.pdf"))
    shutil.copytree(ROOT / "figures", tmp / "figures")
    env = dict(os.environ, SOURCE_DATE_EPOCH="0", FORCE_SOURCE_DATE="1")
    run = subprocess.run(["latexmk", "-r", "latexmkrc", "-outdir=build", "report.tex"], cwd=tmp / "paper",
                         env=env, capture_output=True, text=True, timeout=600)
    log = (tmp / "paper" / "build" / "report.log").read_text(errors="replace")
    assert run.returncode == 0, run.stdout[-3000:] + log[-3000:]
    return tmp / "paper" / "build" / "report.pdf", log


@pytest.mark.slow
def test_report_builds_cleanly_and_deterministically(tmp_path):
    pdf, log = build(tmp_path / "a")
    assert not re.search(r"^! ", log, flags=re.M), "LaTeX error"
    assert "undefined" not in log.lower().replace("undefined control", ""), \
        [line for line in log.splitlines() if "undefined" in line.lower()][:5]
    assert "Overfull" not in log, [line for line in log.splitlines() if "Overfull" in line][:5]
    pdf2, _ = build(tmp_path / "b")
    assert hashlib.sha256(pdf.read_bytes()).digest() == hashlib.sha256(pdf2.read_bytes()).digest()
