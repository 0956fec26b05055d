"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the independent check
of the compiled Lyapunov spectrum.

At one chaotic point (config: lyapunov.independent) the tangent walk's largest exponent against
Benettin's two-trajectory estimate on scipy's solve_ivp (impactdamper.baselines.benettin_ivp:
its own equations, parameter conversion and impact law; no library code), with both errors and
their difference (:func:`impactdamper.studies.lyapunov.independent.independent_check`).

Output: ``figures/lyapunov_independent.json`` (deterministic) and the estimate's CPU time
(``results/benchmarks/lyapunov_independent_cpu.json``, a timing).
"""

from impactdamper.reporting.records import run_stage, write_json
from impactdamper.studies.config import parameters
from impactdamper.studies.lyapunov.independent import independent_check


def main(reference: dict, lyapunov: dict, out_json, cpu_json, log=None) -> dict:
    c = lyapunov["independent"]
    p = parameters(reference).replace(gap=float(c["gap"]))
    out, cpu = independent_check(p, {"periods": int(lyapunov["checks"]["periods"])}, c)
    if log is not None:
        log.info("independent Benettin at gap %g: %s (%.1f CPU-s)", p.gap, out, cpu)
    write_json(out_json, out, indent=1)
    write_json(cpu_json, {"gap": p.gap, "periods": out["ivp"]["periods"], "cpu_s": cpu})
    return out


JOB = "params.reference params.lyapunov output.json output.cpu log=log"
STAGE = {"logger": "lyapunov_independent", "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
