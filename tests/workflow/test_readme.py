"""The README's numbers come from the workflow: its generated block is a verbatim copy of
figures/readme_summary.md (written by workflow/scripts/readme_summary.py), and the two
commands it documents are the ones CI and users run."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BEGIN = "<!-- BEGIN generated: figures/readme_summary.md -->"
END = "<!-- END generated -->"


def test_readme_results_block_is_the_generated_summary():
    readme = (ROOT / "README.md").read_text()
    assert readme.count(BEGIN) == 1 and readme.count(END) == 1
    block = readme.split(BEGIN)[1].split(END)[0].strip("\n") + "\n"
    assert block == (ROOT / "figures" / "readme_summary.md").read_text()


def test_ci_runs_the_readme_test_command():
    readme = (ROOT / "README.md").read_text()
    commands = re.findall(r"^\s*(\.venv/bin/python -m pytest[^#\n]*)", readme, flags=re.M)
    assert commands, "the README must show its test command"
    ci = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()]
    assert commands[0].strip() in ci
