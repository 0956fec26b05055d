"""Times the README's commands as a new user meets them, into ``figures/command_times.json``.

A fresh clone of this repository's HEAD in a scratch directory (with the ``shared`` folder that
sits beside the repository linked beside the clone), then, in the clone and in this order: the
set-up (``bash tools/setup.sh``), the whole workflow (``.venv/bin/snakemake --cores 2
--forceall``), the coarse run (``... --configfile config/ci.yaml``) and the quick test tier. Each command's wall time, the processor time of it and its children, and the
machine's load average just before it are written; the README quotes the file and
tests/workflow/test_readme.py holds it to it. Run it on an idle machine: the figures are that
machine's. Standard library only (before the set-up there is no virtual environment)::

    python3 tools/time_commands.py [--keep DIR]

``--keep DIR`` makes the clone in DIR (a new directory) and leaves it there with everything the
run made (otherwise it is made in a temporary directory and removed).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "figures" / "command_times.json"
# (name, command, what it is), in the README's order.
COMMANDS = [
    ("setup", "bash tools/setup.sh", "the set-up"),
    ("workflow", ".venv/bin/snakemake --cores 2 --forceall", "the whole workflow"),
    ("coarse", ".venv/bin/snakemake --cores 2 --forceall --configfile config/ci.yaml", "the coarse run"),
    ("quick_tests", '.venv/bin/python -m pytest -m "not slow"', "the quick test tier"),
]


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(command: str, cwd: Path, log: Path) -> dict:
    """One command run by bash in ``cwd`` (its output to ``log``): wall and processor seconds."""
    load = os.getloadavg()[0]
    t, c = time.perf_counter(), _children_cpu()
    with open(log, "w") as f:
        done = subprocess.run(["bash", "-c", command], cwd=cwd, stdout=f, stderr=subprocess.STDOUT)
    wall, cpu = time.perf_counter() - t, _children_cpu() - c
    return {
        "command": command,
        "exit_code": done.returncode,
        "wall_s": round(wall, 1),
        "cpu_s": round(cpu, 1),
        "load_before": round(load, 2),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--keep", type=Path, help="leave the clone at this (new) directory")
    args = ap.parse_args()
    if args.keep is not None and args.keep.exists():
        sys.exit(f"time_commands: --keep {args.keep} exists already: name a new directory")
    shared = REPO.parent / "shared"
    if not shared.is_dir():
        sys.exit(f"time_commands: the shared folder beside the repository ({shared}) is missing")
    commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPO, capture_output=True, text=True, check=True)
    if args.keep is not None:
        args.keep.mkdir(parents=True)
    scratch = args.keep.resolve() if args.keep is not None else Path(tempfile.mkdtemp(prefix="impactdamper-timed-"))
    clone = scratch / "repo"
    subprocess.run(["git", "clone", "-q", str(REPO), str(clone)], check=True)
    (scratch / "shared").symlink_to(shared, target_is_directory=True)
    record = {
        "what": "the README's commands timed from a fresh clone (tools/time_commands.py)",
        "commit": commit.stdout.strip(),
        "date": datetime.date.today().isoformat(),
        "machine": platform.platform(),
        "cores": os.cpu_count(),
        "commands": {},
    }
    for name, command, what in COMMANDS:
        print(f"time_commands: {what}: {command}", flush=True)
        done = record["commands"][name] = {"what": what, **timed(command, clone, scratch / f"{name}.log")}
        OUT.write_text(json.dumps(record, indent=1) + "\n")  # what is measured so far
        print(f"time_commands: {done['wall_s']} s wall", flush=True)
        if done["exit_code"] != 0:
            sys.exit(f"time_commands: `{command}` exited {done['exit_code']}; its output is in {scratch / name}.log")
    if args.keep is None:
        shutil.rmtree(scratch, ignore_errors=True)
    else:
        print(f"time_commands: the clone is at {clone}")
    print(f"time_commands: wrote {OUT}")


if __name__ == "__main__":
    main()
