"""The README's set-up on Debian's own interpreter.

Debian 12 and Ubuntu >= 23.04 mark their system Python as externally managed (PEP 668), so
`pip install` outside a virtual environment fails there. `tools/setup.sh` makes the project's
own `.venv/`; this test runs it in a scratch copy of the working tree with `/usr/bin/python3`
as the only `python3` on PATH (no pyenv, no conda), runs it a second time (safe to run again),
then plans the workflow and collects the tests with the interpreter it made.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DEBIAN_PYTHON = Path("/usr/bin/python3")
# pip install of the pinned packages takes ~2 min from pip's cache on 2 cores.
SETUP_TIMEOUT = 1200


def copy_work_tree(dest: Path) -> None:
    """Tracked and untracked-but-not-ignored files: what a clone of this state would hold."""
    files = (
        subprocess.run(
            ["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, check=True, capture_output=True
        )
        .stdout.decode()
        .split("\0")
    )
    for name in filter(None, files):
        src = ROOT / name
        if src.is_file():
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)


def debian_env(bin_dir: Path) -> dict[str, str]:
    env = {
        k: v
        for k, v in os.environ.items()
        if not k.startswith(("PYENV", "CONDA", "VIRTUAL_ENV", "PYTHON")) and k != "PATH"
    }
    # Only /usr/bin's python3: the scratch bin/ links it first, and no pyenv shims follow.
    env["PATH"] = os.pathsep.join([str(bin_dir), "/usr/local/sbin", "/usr/sbin", "/usr/bin", "/sbin", "/bin"])
    return env


@pytest.mark.slow
def test_setup_with_debian_system_python(tmp_path):
    assert DEBIAN_PYTHON.exists(), "this check runs on Debian's own /usr/bin/python3"
    version = subprocess.run([DEBIAN_PYTHON, "--version"], capture_output=True, text=True, check=True).stdout.strip()
    repo, bin_dir = tmp_path / "repo", tmp_path / "bin"
    repo.mkdir()
    bin_dir.mkdir()
    (bin_dir / "python3").symlink_to(DEBIAN_PYTHON)
    copy_work_tree(repo)
    env = debian_env(bin_dir)
    which = subprocess.run(
        ["bash", "-c", "command -v python3 && python3 --version"], env=env, capture_output=True, text=True, check=True
    ).stdout.split()
    assert which[0] == str(bin_dir / "python3") and " ".join(which[1:]) == version

    first = subprocess.run(
        ["bash", "tools/setup.sh"], cwd=repo, env=env, capture_output=True, text=True, timeout=SETUP_TIMEOUT
    )
    assert first.returncode == 0, first.stderr[-3000:]
    assert f"setup: made .venv with {version}" in first.stdout
    assert "setup: compiled kernels ready" in first.stdout  # numba's cache filled at set-up
    cfg = (repo / ".venv" / "pyvenv.cfg").read_text()
    assert f"executable = {DEBIAN_PYTHON.resolve()}" in cfg.splitlines(), cfg

    again = subprocess.run(
        ["bash", "tools/setup.sh"], cwd=repo, env=env, capture_output=True, text=True, timeout=SETUP_TIMEOUT
    )
    assert again.returncode == 0, again.stderr[-3000:]
    assert "made .venv" not in again.stdout  # the existing venv is reused
    assert "setup: done" in again.stdout

    venv_bin = repo / ".venv" / "bin"
    # The console script (pyproject.toml [project.scripts]) beside `python -m impactdamper`.
    alg1 = subprocess.run(
        [venv_bin / "impactdamper", "alg1", "--json"], cwd=repo, env=env, capture_output=True, text=True, timeout=600
    )
    assert alg1.returncode == 0 and json.loads(alg1.stdout)["exists"] is True, alg1.stderr[-3000:]
    plan = subprocess.run(
        [venv_bin / "snakemake", "-n", "--cores", "2", "--forceall", "--configfile", "config/ci.yaml"],
        cwd=repo,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert plan.returncode == 0, plan.stderr[-3000:]
    jobs = re.search(r"^total\s+(\d+)", plan.stdout + plan.stderr, flags=re.M)
    assert jobs and int(jobs.group(1)) >= 40, (plan.stdout + plan.stderr)[-2000:]

    collect = subprocess.run(
        [venv_bin / "python", "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider"],
        cwd=repo,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert collect.returncode == 0, collect.stdout[-3000:]
    collected = re.search(r"^(\d+) tests collected", collect.stdout, flags=re.M)
    assert collected and int(collected.group(1)) > 100, collect.stdout[-2000:]
