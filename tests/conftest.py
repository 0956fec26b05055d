"""Test configuration.

The solver's matrices are 4 x 4: BLAS threads never help them, and on a loaded machine
OpenBLAS's thread hand-offs made the matrix-exponential path (repeated roots) up to ~90 times
slower (8.4 s against 0.09 s for one steady state at load 8 on 2 cores).
One thread per BLAS, set before numpy is first imported (an explicit setting wins); and the
record's OpenBLAS family (below)."""

import importlib.util
import os
import sys
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")


def _pin_record_blas() -> str:
    """Pin the OpenBLAS family the workflow pins its jobs to (workflow/rules/reproducibility.smk),
    by its one definition, loaded without importing the package (which would load numpy first)."""
    path = Path(__file__).resolve().parents[1] / "src" / "impactdamper" / "reporting" / "record_tolerances.py"
    spec = importlib.util.spec_from_file_location("_record_tolerances", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # (its dataclasses look their module up there)
    spec.loader.exec_module(module)
    del sys.modules[spec.name]
    return module.pin_record_blas()


# The tests that regenerate parts of the record compare them with files the workflow made under
# that family: they run under it too (and so do the subprocesses they start), so that they judge
# the code, not this processor's OpenBLAS routines.
_pin_record_blas()
