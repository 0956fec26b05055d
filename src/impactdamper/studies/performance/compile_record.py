"""The JIT compile time of the compiled solver's kernels, measured once.

Compiling the numba kernels from scratch takes a minute or two; loading them from numba's cache
about a second. :func:`compile_times` measures both, each in a fresh process (the compile into
an empty cache of its own). It is measured once at set-up (``tools/setup.sh`` calls
:func:`write_compile_record`, beside compiling the kernels into the project's cache), into a
record that the workflow reads while it is current (:func:`current_compile_record`: the same
kernels' sources and numba version); where it is missing or stale, the workflow's rule
performance_compile_time measures it in the run. The record says which (``measured``).

This module imports neither numba nor the kernels: the workflow asks it which record to read
while it plans its jobs.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
from importlib import metadata
from pathlib import Path

import impactdamper

__all__ = [
    "MEASURED_AT_SETUP",
    "MEASURED_IN_RUN",
    "compile_times",
    "compile_record",
    "write_compile_record",
    "current_compile_record",
]

# Where the compile time was measured (the record's ``measured``): once at set-up
# (tools/setup.sh), or by the workflow's own job where the set-up's record is missing or stale.
MEASURED_AT_SETUP, MEASURED_IN_RUN = "set-up", "workflow"


def compile_times() -> dict:
    """Kernels compiled into an empty cache, then loaded from it, each in a fresh process."""
    code = (
        "import time; t = time.perf_counter(); from impactdamper.core.backends import warm_up; warm_up('compiled'); "
        "print(time.perf_counter() - t)"
    )
    out = {}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for name in ("cold_compile_s", "cached_load_s"):
            run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
            out[name] = float(run.stdout.strip().splitlines()[-1])
    out["load_1min"] = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
    return out


def _sources_fingerprint() -> str:
    """A digest of the sources the kernels are compiled from (the package's ``core/``) and of
    numba's version: what numba's cache depends on. A compile time measured for others is stale."""
    core = Path(impactdamper.__file__).parent / "core"
    digest = hashlib.sha256(metadata.version("numba").encode())
    for path in sorted(core.rglob("*.py")):
        digest.update(str(path.relative_to(core)).encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


def compile_record(measured: str) -> dict:
    """The compile times (:func:`compile_times`) with where they were ``measured``, the sources'
    fingerprint and the machine."""
    return {
        "compile": compile_times(),
        "measured": measured,
        "sources": _sources_fingerprint(),
        "numba": metadata.version("numba"),
        "machine": {"cpu_count": os.cpu_count(), "platform": platform.platform()},
    }


def write_compile_record(path) -> dict:
    """Measure the compile times once (at set-up) into ``path`` (JSON)."""
    record = compile_record(MEASURED_AT_SETUP)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(json.dumps(record, indent=2) + "\n")
    return record


def current_compile_record(path) -> bool:
    """Whether ``path`` holds a compile record of the present sources (:func:`sources_fingerprint`)."""
    try:
        record = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return False
    return isinstance(record, dict) and "compile" in record and record.get("sources") == _sources_fingerprint()
