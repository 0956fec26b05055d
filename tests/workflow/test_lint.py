"""Lint and format as CI runs them (configured in pyproject.toml: [tool.ruff], [tool.snakefmt])."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    "command",
    [
        ["ruff", "check", "."],
        ["ruff", "format", "--check", "."],
        ["snakefmt", "--check", "."],
    ],
    ids=["ruff-check", "ruff-format", "snakefmt"],
)
def test_lint_and_format_are_clean(command):
    out = subprocess.run([sys.executable, "-m", *command], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, (out.stdout + out.stderr)[-4000:]


def test_figure_scripts_take_sizes_from_the_shared_style():
    """No figure script sets a size in numbers: the width is the style's (plotting.figure_size),
    text sizes are the style's or relative to its font size ("small", plotting.ANNOTATION_SIZE),
    so that paper.mplstyle alone sizes every figure."""
    import re

    from impactdamper.reporting.plotting import TEXT_WIDTH, figure_size

    style = (ROOT / "src" / "impactdamper" / "reporting" / "paper.mplstyle").read_text()
    assert re.search(r"^figure\.figsize: ([\d.]+),", style, flags=re.M).group(1) == str(TEXT_WIDTH)
    assert figure_size(3.0) == (TEXT_WIDTH, 3.0)
    scripts = sorted((ROOT / "workflow" / "scripts").glob("fig*.py"))
    assert len(scripts) >= 14
    numeric = re.compile(r"\b(?:fontsize|title_fontsize|size)\s*=\s*[\d.]+|figsize\s*=\s*\(|rcParams")
    found = [
        f"{p.name}:{i}: {line.strip()}"
        for p in scripts
        for i, line in enumerate(p.read_text().splitlines(), 1)
        if numeric.search(line) or re.match(r"^[A-Z_]*SIZE\s*=\s*[\d.]+", line)
    ]
    assert found == [], "\n".join(found)
