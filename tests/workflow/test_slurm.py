"""The cluster profile on a real Slurm scheduler.

Runs ``tools/slurm_check.sh``: a single-node Slurm on this machine (slurm-wlm and munge from apt
when missing; needs root), the CI config's regime-map stage through Slurm with
``--profile profiles/slurm`` and locally with ``--cores 2``, and a byte-for-byte comparison of
every output but the timing JSON files. About 2 min including the apt install on a fresh
machine (profiles/slurm/check_record.txt). Never skipped: a machine where the check cannot run
fails here.
"""

import os
import re
import subprocess
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]

# Outputs compared per map: its chunk CSVs (maps.chunks of them), and the gathered map CSV,
# its settings JSON, its analytic curves CSV, the figure's PDF and PNG.
MAPS = ["theta", "damping"]
PER_MAP = 5  # so 14 files for config/ci.yaml (2 maps, 2 chunks each)


def ci_chunks() -> int:
    return yaml.safe_load((ROOT / "config" / "ci.yaml").read_text())["maps"]["chunks"]


def expected_count() -> int:
    return len(MAPS) * (ci_chunks() + PER_MAP)


@pytest.mark.slow
def test_map_stage_through_slurm_matches_local_run(tmp_path):
    out = subprocess.run(
        ["bash", str(ROOT / "tools" / "slurm_check.sh")],
        cwd=ROOT,
        env={**os.environ, "SLURM_CHECK_DIR": str(tmp_path / "check")},
        capture_output=True,
        text=True,
        timeout=1200,
    )
    log = out.stdout + out.stderr
    assert out.returncode == 0, log[-6000:]
    # Every job went through Slurm: the compiled kernels' warm-up once, then per map map_chunk
    # per chunk, map_gather, map_curves, fig_regime_map.
    jobids = set(re.findall(r"submitted with SLURM jobid (\d+)", log))
    assert len(jobids) == 1 + len(MAPS) * (ci_chunks() + 3), log[-6000:]
    summary = re.findall(r"^(\d+) identical, (\d+) differ$", log, flags=re.M)
    assert summary == [(str(expected_count()), "0")], log[-6000:]
