"""The committed coarse record and its machine dependence, measured: run from the repository,

    .venv/bin/python tools/coarse_record.py

It regenerates a few stages of the coarse configuration (config/ci.yaml; ``TARGETS``) three
times, each under its own output root in results/coarse_record/: once as this machine runs them
(the reference), and once under each of ``EMULATED`` OpenBLAS kernel families
(``OPENBLAS_CORETYPE``: what another CPU would run). The reference's record (figures/ and
paper/generated/) becomes tests/data/coarse_record/, and each emulated run is checked against it
(``python -m impactdamper check-record``, with the coarse record's tolerances.json): the verdicts
and counts go to tests/data/coarse_record/emulation.json, which the README, the report (rule
reproducibility_macros) and the CI test (tests/workflow/test_reproduction.py) read. About 10 min
of CPU on two cores. Rerun it whenever the stages' code or config/ci.yaml changes.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
from impactdamper.reporting.record_tolerances import BLAS_CORETYPE_OVERRIDE, RECORD_BLAS_CORETYPE  # noqa: E402
from impactdamper.reporting.recordcheck import check_record, emulation_summary  # noqa: E402

RECORD = ROOT / "tests" / "data" / "coarse_record"
SCRATCH = "results/coarse_record"
# The stages regenerated: the gap sweep and its transitions, both regime maps, the claims'
# parameter scans, one pair map and the gap scan of the reference stage (3 min on one core).
TARGETS = (
    "figures/sweep_gap.csv",
    "figures/sweep_transitions.csv",
    "figures/map_theta.csv",
    "figures/map_damping.csv",
    "figures/claims_by_parameter.csv",
    "figures/claims_map_theta_gap.csv",
    "figures/gap_scan.csv",
)
# Kernel families another machine would run, where the workflow's pin (RECORD_BLAS_CORETYPE,
# workflow/rules/reproducibility.smk) does not hold (OpenBLAS names; it reports which it
# loaded). PINNED: the family an environment names, which the pin overrides (identical record).
EMULATED = ("Sandybridge", "Haswell")
PINNED = "SkylakeX"


def openblas_cores(env: dict) -> list[str]:
    """The kernel family each OpenBLAS that numpy and scipy load reports under ``env``."""
    code = (
        "import ctypes, numpy, scipy.linalg\n"
        "paths = sorted({l.split()[-1] for l in open('/proc/self/maps') if 'openblas' in l.rsplit('/', 1)[-1].lower()})\n"
        "for p in paths:\n"
        "    lib = ctypes.CDLL(p)\n"
        "    for s in ('scipy_openblas_get_corename64_', 'scipy_openblas_get_corename', 'openblas_get_corename'):\n"
        "        if hasattr(lib, s):\n"
        "            f = getattr(lib, s); f.restype = ctypes.c_char_p; print(f().decode()); break\n"
    )
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return sorted(set(out.stdout.split()))


def regenerate(root: str, env: dict, targets=TARGETS, cores: int = 2) -> Path:
    """The coarse run of ``targets`` under output root ``root`` (a path under results/)."""
    command = [sys.executable, "-m", "snakemake", *targets, "--cores", str(cores), "--forceall"]
    command += ["--configfile", "config/ci.yaml", "--config", f"output_root={root}"]
    out = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"coarse_record: the run {root} failed:\n{(out.stdout + out.stderr)[-4000:]}")
    return ROOT / root


def main() -> None:
    base = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    base.pop(BLAS_CORETYPE_OVERRIDE, None)  # the reference runs with the workflow's pin
    reference = regenerate(f"{SCRATCH}/reference", base)
    tolerances = (RECORD / "tolerances.json").read_text() if (RECORD / "tolerances.json").is_file() else None
    shutil.rmtree(RECORD, ignore_errors=True)
    for part in ("figures", "paper/generated"):
        if (reference / part).is_dir():
            shutil.copytree(reference / part, RECORD / part)
    if tolerances is not None:
        (RECORD / "tolerances.json").write_text(tolerances)
    runs = {}
    for family in EMULATED:
        env = {**base, BLAS_CORETYPE_OVERRIDE: family, "OPENBLAS_CORETYPE": family}
        verdicts = check_record(regenerate(f"{SCRATCH}/{family}", env), str(RECORD), ROOT)
        runs[family] = {"openblas": openblas_cores(env), **emulation_summary(verdicts)}
        print(f"coarse_record: {family}: {runs[family]['summary']}", flush=True)
    env = {**base, "OPENBLAS_CORETYPE": PINNED}
    pinned = emulation_summary(check_record(regenerate(f"{SCRATCH}/pinned", env), str(RECORD), ROOT))
    print(f"coarse_record: {PINNED} in the environment, pinned: {pinned['summary']}", flush=True)
    record = {
        "what": "the coarse record (config/ci.yaml, the stages of 'targets') made on this machine, and the same "
        "stages under other OpenBLAS kernel families checked against it (tools/coarse_record.py)",
        "targets": list(TARGETS),
        "reference_openblas": openblas_cores({**base, "OPENBLAS_CORETYPE": RECORD_BLAS_CORETYPE}),
        "reference_environment": os.environ.get("OPENBLAS_CORETYPE", "(unset: OpenBLAS detects the CPU)"),
        "runs": runs,
        "pinned": {"environment": PINNED, **pinned},
    }
    (RECORD / "emulation.json").write_text(json.dumps(record, indent=1) + "\n")
    print(f"coarse_record: wrote {RECORD.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
