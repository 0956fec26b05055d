"""Test configuration.

The solver's matrices are 4 x 4: BLAS threads never help them, and on a loaded machine
OpenBLAS's thread hand-offs made the matrix-exponential path (repeated roots) up to ~90 times
slower (8.4 s against 0.09 s for one steady state at load 8 on 2 cores).
One thread per BLAS, set before numpy is first imported (an explicit setting wins)."""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
