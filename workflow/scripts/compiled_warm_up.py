"""Compiles the library's numba kernels once, before any job that uses them.

The compiled exact solver (the backend ``"compiled"`` of :mod:`impactdamper.core.backends`,
:mod:`impactdamper.core.compiled`) keeps its machine code in numba's on-disk cache. Compiling
from scratch takes tens of seconds; loading from the cache about a second. Every rule that runs
compiled code takes this rule's output as an input, so that parallel jobs load the cache instead
of each compiling the same kernels. The rule lists the library as input: a change to the kernels
reruns it (numba's cache is keyed on the source files too).

Output: ``results/compiled/warm_up.json`` -- the seconds the warm-up took (compile or load),
numba's version and the machine's load (not deterministic).
"""

import numba

from impactdamper.core.backends import warm_up
from impactdamper.reporting.records import machine, run_stage, write_json


def main(out_json, log=None) -> dict:
    seconds = warm_up("compiled")
    out = {"seconds": seconds, "numba": numba.__version__, "machine": machine()}
    write_json(out_json, out, indent=2)
    if log is not None:
        log.info("kernels compiled or loaded in %.1f s", seconds)
    return out


if __name__ == "__main__":
    run_stage(snakemake, main, "output.json log=log", logger="compiled_warm_up", timestamps=True)  # noqa: F821 (injected by Snakemake's script: directive)
