"""Speed of the compiled exact solver against the pure-Python one and solve_ivp DOP853.

In one run, on the paper's reference case (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100, Fig. 2: theta = 1, mu = 0.08, N = 0.5,
delta1 = delta2 = 0.05, R = 0.7, Delta0/x_st = -5.8, omega = 10 rad/s), with the measurement
functions of ``impactdamper.studies.performance.compiled_speed``:

* JIT compile time (rule performance_compile_time, ``compile_only``, where the set-up's record of
  it is missing or stale: :mod:`impactdamper.studies.performance.compile_record`): the kernels
  compiled from scratch (a fresh numba cache, in a subprocess), and loaded from the cache (a
  second subprocess), each on its own line;
* microseconds per impact over a long run (>= 1e4 impacts), for the compiled solver; the
  pure-Python solver and DOP853 over a shorter part of the same run (their cost per impact is
  flat in the run's length);
* the reference case's settled motion (``steady_state``), with its phase error against
  Algorithm No. 1's closed form (eqs. 13-17) and against the pure-Python steady state;
* the first 10 impacts from Algorithm No. 2's step 1;
* the front door: median ``impactdamper.steady_state(Parameters())`` after warm-up (auto backend)
  beside the Python backend's; a batch of ``performance.compiled_speed_batch_points`` points (a
  gap x theta grid, each from Algorithm No. 2's step 1) through ``impactdamper.steady_states``
  against the kernels' own time on the same points; ``python -m impactdamper steady --json`` wall
  time from a warm cache, import included (a fresh process each);
* regime maps of ``performance.compiled_speed_map_sizes`` (n x n: Delta0/x_st in [-40, 15]
  against theta in [0.5, 1.5], each row swept upward, cell from cell, with the config's
  ``maps`` settle settings) through the batch entry point, split over the rule's threads as the
  workflow's chunks would be (rule performance_compiled_map, ``maps_only``: the only part that
  needs both cores, so it runs alone, timed ``performance.compiled_speed_map_repeats`` times);
  DOP853 and the pure-Python map are timed on a sample of the map's points and rows and
  extrapolated by simulated periods (saying so).

Every timing is CPU time of the timed process (time.process_time) and wall time, minimum and
median of ``performance.compiled_speed_repeats`` runs, with the 1-minute load average beside it
(the machine is shared). Targets: ``performance.compiled_speed_targets`` of the config.

Outputs: ``figures/compiled_speed.json`` (its 'compile' null) or, with ``compile_only``,
``results/benchmarks/compile_time.json`` ({'compile': ...}). Timings are not deterministic.
"""

from impactdamper.reporting.records import read_json, start_stage, write_json
from impactdamper.studies.performance.compile_record import MEASURED_IN_RUN, compile_record
from impactdamper.studies.performance.compiled_speed import run, run_maps, summary


def main(params: dict, output, workers: int = 2, log=print, maps_json=None) -> dict:
    """The benchmark's record from the rule's ``params`` (``compile_only``; ``maps_only``: the
    regime maps alone, timed on ``workers`` processes; or ``repeats``, ``batch_points``,
    ``targets`` and ``maps``, the settle settings of the config's maps section, with the maps'
    record ``maps_json`` (rule performance_compiled_map's) or the maps timed here too), written
    to ``output``."""
    if params.get("compile_only"):
        record = compile_record(MEASURED_IN_RUN)
        write_json(output, record)
        log(
            f"JIT compile from scratch: {record['compile']['cold_compile_s']:.1f} s; "
            f"load from the cache: {record['compile']['cached_load_s']:.2f} s"
        )
        return record
    sizes = [int(n) for n in params["map_sizes"]]
    if params.get("maps_only"):
        record = run_maps(
            params["targets"], params["maps"], map_repeats=int(params["map_repeats"]), workers=workers, map_sizes=sizes
        )
        write_json(output, record)
        log(", ".join(f"map {k}: wall {m['wall_min_s']:.1f} s on {m['workers']} processes" for k, m in record.items()))
        return record
    record = run(
        params["targets"],
        params["maps"],
        repeats=int(params["repeats"]),
        workers=workers,
        map_sizes=sizes,
        batch_points=int(params["batch_points"]),
        compile_time=False,  # (timed once at set-up, or by rule performance_compile_time)
        maps=read_json(maps_json) if maps_json else None,
    )
    write_json(output, record)
    log(summary(record))
    return record


if __name__ == "__main__":
    sm = snakemake  # noqa: F821 (injected by Snakemake's script: directive)
    cfg, lg = start_stage(sm, "compiled_speed")
    main(cfg, sm.output[0], workers=sm.threads, log=lg.info, maps_json=getattr(sm.input, "maps", None))
