"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the cost of one point's
Lyapunov spectrum, compiled against the reference, and of the command.

A benchmark, not a result: CPU times (the least of ``lyapunov.speed_repeats`` for the compiled
walk, one run of the reference), from the paper's step 1, ``lyapunov.speed_periods`` periods
averaged, at the stated case, a chaotic point and a chatter cycle
(:func:`impactdamper.studies.lyapunov.checks.speed`); and the wall time of
``python -m impactdamper lyapunov --json`` in a new process.

Output: ``results/benchmarks/lyapunov_speed.json`` (timings: not part of the record).
"""

from impactdamper.reporting.records import machine, run_stage, write_json
from impactdamper.studies.lyapunov.checks import command_wall, speed


def main(lyapunov: dict, out_json, log=None) -> dict:
    out = {
        "speed": speed(lyapunov["speed_gaps"], int(lyapunov["speed_periods"]), int(lyapunov["speed_repeats"])),
        "command": "python -m impactdamper lyapunov --gap -16 --json",
        "command_wall_s": command_wall(["--gap", "-16"], int(lyapunov["speed_repeats"])),
        "machine": machine(),
    }
    write_json(out_json, out, indent=2)
    if log is not None:
        log.info("%s", out)
    return out


JOB = "params.lyapunov output.json log=log"
STAGE = {"logger": "lyapunov_speed", "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
