"""A coarse run (config/ci.yaml) writes under its own output root, never over the record.

config/ci.yaml holds only what differs from config/config.yaml and sets ``output_root:
results/ci``; the Snakefile makes that root the working directory (workflow/rules/output_root.smk)
and links the sources into it. The test plans the coarse DAG and then has Snakemake create every
planned output (``--touch``: no job runs) in a scratch copy of the repository: every file it
makes lies under results/ci, and nothing in the record (figures/, paper/) changes. A dry run
writes nothing at all: no root, no link, not even Snakemake's bookkeeping in the root (it plans
in a temporary directory, removed at exit).
"""

import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "--nolock"]
RECORD = ("figures", "paper")


def _snakemake(repo: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")]))}
    return subprocess.run([*SNAKEMAKE, *args], cwd=repo, env=env, capture_output=True, text=True, timeout=300)


def _tree(top: Path) -> dict[str, tuple[int, int]]:
    """Relative path -> (size, mtime in ns) of every file, directory and link under ``top`` (links
    not followed)."""
    return {str(p.relative_to(top)): (p.lstat().st_size, p.lstat().st_mtime_ns) for p in top.rglob("*")}


def _dry_run_writes_nothing(repo: Path, *args: str) -> subprocess.CompletedProcess:
    """A dry run in ``repo``; asserts that no file, directory or link under it changed and that
    its planning directory is gone."""
    before = _tree(repo)
    out = _snakemake(repo, "-n", *args)
    assert out.returncode == 0, (out.stdout + out.stderr)[-3000:]
    assert _tree(repo) == before
    plan = re.search(r"planned in (\S+) \(removed at exit\)", out.stderr)
    assert plan is not None and not Path(plan.group(1)).exists(), out.stderr[-2000:]
    return out


def _files(top: Path) -> dict[str, tuple[int, int]]:
    """Relative path -> (size, mtime in ns) of every file under ``top``."""
    return {str(p.relative_to(top)): (p.stat().st_size, p.stat().st_mtime_ns) for p in top.rglob("*") if p.is_file()}


@pytest.fixture(scope="module")
def copy(tmp_path_factory) -> Path:
    """The repository's files (tracked and untracked, not ignored) in a scratch directory."""
    repo = tmp_path_factory.mktemp("repo")
    listed = (
        subprocess.run(
            ["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, capture_output=True, check=True
        )
        .stdout.decode()
        .split("\0")
    )
    for name in filter(None, listed):
        source = ROOT / name
        if source.is_file():
            (repo / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, repo / name)
    return repo


def test_ci_config_holds_only_what_differs():
    """Every value in config/ci.yaml differs from config/config.yaml's (a list counts whole)."""
    base = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    ci = yaml.safe_load((ROOT / "config" / "ci.yaml").read_text())

    def same(over, under, path=()):
        for key, value in over.items():
            if isinstance(value, dict) and isinstance(under.get(key), dict):
                yield from same(value, under[key], path + (key,))
            elif key in under and under[key] == value:
                yield path + (key,)

    assert ci["output_root"] == "results/ci"
    assert list(same(ci, base)) == []
    # Well below the full file's length (config.yaml; the overlay was once a 195-line copy of it):
    # the overlay grows only by the keys that differ.
    lines = len((ROOT / "config" / "ci.yaml").read_text().splitlines())
    assert lines < len((ROOT / "config" / "config.yaml").read_text().splitlines()) / 2, lines


@pytest.mark.slow
def test_coarse_run_writes_only_under_its_root(copy):
    assert not (copy / "results").exists()
    # The plan: a dry run, which makes no root and writes nothing anywhere (it used to make
    # results/ci and fill it with links).
    plan = _dry_run_writes_nothing(copy, "--forceall", "--configfile", "config/ci.yaml")
    assert not (copy / "results").exists()
    planned = set()
    for line in re.findall(r"^\s+output: (.*)$", plan.stdout, flags=re.M):
        planned |= {f.strip() for f in line.split(",")}
    assert len(planned) > 100 and "paper/report.pdf" in planned and "figures/fig2a_stated.pdf" in planned

    # Every planned output, made empty under the root a day ago, then touched by Snakemake
    # (--touch runs no job; it touches the outputs it finds where the run puts them, and names
    # those it does not find): each one is found under results/ci and touched.
    root = copy / "results" / "ci"
    old = 1_000_000_000 * (int(time.time()) - 86_400)
    for name in planned:
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).touch()
        os.utime(root / name, ns=(old, old))
    before = _files(copy)
    made = _snakemake(copy, "--cores", "1", "--touch", "--forceall", "--configfile", "config/ci.yaml")
    assert made.returncode == 0, (made.stdout + made.stderr)[-3000:]
    assert "not touched" not in made.stdout + made.stderr, (made.stdout + made.stderr)[-3000:]
    after = _files(copy)
    assert all(after[f"results/ci/{name}"][1] > old for name in planned)
    assert (root / "logs" / "report.log").is_file()  # the logs too
    # Outside the root: the same files, unchanged (figures/ and paper/ above all), besides
    # Snakemake's own run log in the git-ignored .snakemake/log/.
    outside = {p: v for p, v in after.items() if not p.startswith(("results/ci/", ".snakemake/log/"))}
    assert outside == {p: v for p, v in before.items() if not p.startswith("results/ci/")}
    assert sum(p.startswith(RECORD) for p in outside) > 100
    # A dry run over the filled root plans it where it is (every output up to date, as the
    # root's own files and record of the last run say) and still writes nothing, in it either.
    again = _dry_run_writes_nothing(copy, "--configfile", "config/ci.yaml")
    assert "Nothing to be done" in again.stdout + again.stderr, (again.stdout + again.stderr)[-3000:]


@pytest.mark.slow
@pytest.mark.parametrize("root", ["figures/ci", "paper", "src/out", "results", "../outside", "ABSOLUTE", "."])
def test_output_root_outside_the_scratch_is_refused(tmp_path, root):
    """A root anywhere but under results/ stops the plan with one line naming the key, before
    anything is written ("." is the record run itself: allowed). ("/" is refused the same way:
    tests/unit/test_config_check.py, in process, so that no regression can write there.)"""
    root = str(tmp_path / "out") if root == "ABSOLUTE" else root
    override = tmp_path / "root.yaml"
    override.write_text(f"output_root: {root}\n")
    out = _snakemake(ROOT, "-n", "reference", "--configfile", "config/ci.yaml", str(override))
    text = out.stdout + out.stderr
    if root == ".":
        assert out.returncode == 0, text[-3000:]
        return
    assert out.returncode != 0
    message = (
        f"Error validating config file: ['output_root']: '{root}' is not allowed: must be '.' or a relative path "
        "under results/ (the git-ignored scratch), such as results/ci"
    )
    assert message in text and len(text.splitlines()) < 10, text  # one line and Snakemake's frame lines
    assert not (ROOT / root / "paper").exists() and not (ROOT / root / "src").is_symlink()
    assert not (tmp_path / "out").exists()
