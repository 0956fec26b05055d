"""The whole workflow runs to its end: the coarse run of the README (``snakemake --cores 2
--forceall --configfile config/ci.yaml``: the same DAG and physics on coarse grids and short
budgets, written under its own output root) from scratch, every job done and the report
compiled. A stage that breaks, a figure or record script that fails on coarse data, or a report
that does not compile fails here: the coarse report once stopped on a sentence that only a short
search budget writes, and no other test ran it. A few minutes on two cores; the full run's
records are held to the committed ones by the other workflow tests.
"""

import re
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_the_coarse_run_does_every_job_and_compiles_the_report():
    root = ROOT / yaml.safe_load((ROOT / "config" / "ci.yaml").read_text())["output_root"]
    started = time.time()
    out = subprocess.run(
        [sys.executable, "-m", "snakemake", "--cores", "2", "--forceall", "--configfile", "config/ci.yaml"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=3600,
    )
    log = out.stdout + out.stderr
    assert out.returncode == 0, log[-6000:]
    steps = re.findall(r"^(\d+) of (\d+) steps \(100%\) done$", log, flags=re.M)
    assert steps and steps[-1][0] == steps[-1][1] and int(steps[-1][1]) > 50, log[-3000:]
    for made in ("paper/report.pdf", "figures/fig2b_located.png", "figures/readme_summary.md"):
        path = root / made
        assert path.stat().st_mtime >= started and path.stat().st_size > 0, made
    assert (root / "paper" / "report.pdf").read_bytes().startswith(b"%PDF")
