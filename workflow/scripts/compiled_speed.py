"""Speed of the compiled exact solver against the pure-Python one and solve_ivp DOP853.

In one run, on the paper's reference case (Timofeev et al. 2019, DOI
10.18698/0236-3941-2019-1-90-100, Fig. 2: theta = 1, mu = 0.08, N = 0.5,
delta1 = delta2 = 0.05, R = 0.7, Delta0/x_st = -5.8, omega = 10 rad/s):

* JIT compile time: the kernels compiled from scratch (a fresh numba cache, in a subprocess),
  and loaded from the cache (a second subprocess), each on its own line;
* microseconds per impact over a long run (``--long-periods`` forcing periods, >= 1e4 impacts),
  for the compiled solver; the pure-Python solver and DOP853 over ``--ivp-periods`` of the same
  run (their cost per impact is flat in the run's length);
* the reference case's settled motion (``steady_state``), with its phase error against
  Algorithm No. 1's closed form (eqs. 13-17) and against the pure-Python steady state;
* the first 10 impacts from Algorithm No. 2's step 1;
* the front door: median ``impactdamper.steady_state(Parameters())`` after warm-up (auto backend)
  beside the Python backend's; a batch of ``--batch-points`` points (a gap x theta grid, each
  from Algorithm No. 2's step 1) through ``impactdamper.steady_states`` against the kernels' own
  time on the same points (the steady kernel called directly on pre-packed parameters, no result
  objects); ``python -m impactdamper steady --json`` wall time from a warm cache, import included
  (a fresh process each);
* a 200 x 200 regime map (the full config's theta map: Delta0/x_st in [-40, 15] against
  theta in [0.5, 1.5], each row swept upward, cell from cell) through the batch entry point,
  split over ``--workers`` processes as the workflow's chunks would be; DOP853 and the
  pure-Python map are timed on a sample of the map's points and rows and extrapolated by
  simulated periods (saying so).

Every timing is CPU time of the timed process (time.process_time) and wall time, minimum and
median of ``--repeats`` runs, with the 1-minute load average beside it (the machine is shared).
Targets: ``--targets`` (JSON), default the config's ``performance.compiled_speed_targets``
(config/config.yaml): per impact, the steady state (kernels and front door), its speed-up over
DOP853 and phase error, the first 10 impacts' speed-up, the map's wall time, the batch's ratio to
the kernels, the CLI's wall time.

Usage: ``python workflow/scripts/compiled_speed.py figures/compiled_speed.json [--quick]``
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from impactdamper.studies.performance.compiled_speed import MAP_SETTINGS, TARGETS, compile_times, run, summary

CONFIG = Path(__file__).resolve().parents[2] / "config" / "config.yaml"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("output", type=Path)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--map-repeats", type=int, default=2)
    ap.add_argument("--long-periods", type=int, default=10_000)
    ap.add_argument("--ivp-periods", type=int, default=200)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--map-sizes", type=int, nargs="+", default=[200])
    ap.add_argument(
        "--max-periods",
        type=int,
        default=MAP_SETTINGS["max_periods"],
        help="the map's period cap per point (the config's maps.max_periods)",
    )
    ap.add_argument(
        "--max-periods-after-nonperiodic",
        type=int,
        default=MAP_SETTINGS["max_periods_after_nonperiodic"],
        help="the cap after a nonperiodic neighbour (maps.max_periods_after_nonperiodic)",
    )
    ap.add_argument(
        "--targets",
        default=None,
        help="the targets as JSON (default: performance.compiled_speed_targets of config/config.yaml)",
    )
    ap.add_argument("--batch-points", type=int, default=10_000, help="points of the front door's batch")
    ap.add_argument("--quick", action="store_true", help="a small run (maps 40 x 40, fewer periods) to try it out")
    ap.add_argument(
        "--compile-only",
        action="store_true",
        help="measure only the JIT compile and cache-load times, write {'compile': ...} and stop",
    )
    ap.add_argument(
        "--no-compile",
        action="store_true",
        help="do not measure the compile and cache-load times (a --compile-only run does; the record's "
        "'compile' is then null)",
    )
    args = ap.parse_args(argv)
    if args.targets is None:
        import yaml

        TARGETS.update(yaml.safe_load(CONFIG.read_text())["performance"]["compiled_speed_targets"])
    else:
        try:
            TARGETS.update(json.loads(args.targets))
        except json.JSONDecodeError:
            ap.error(
                f"`--targets` = {args.targets!r} is not allowed: must be a JSON object of the config's "
                "performance.compiled_speed_targets"
            )
    if args.compile_only:
        record = {"compile": compile_times()}
        args.output.parent.mkdir(parents=True, exist_ok=True)
        args.output.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
        print(
            f"JIT compile from scratch: {record['compile']['cold_compile_s']:.1f} s; "
            f"load from the cache: {record['compile']['cached_load_s']:.2f} s"
        )
        return 0
    for name in ("repeats", "map_repeats", "long_periods", "ivp_periods", "workers"):
        if getattr(args, name) < 1:
            ap.error(f"`--{name.replace('_', '-')}` = {getattr(args, name)} is not allowed: must be >= 1")
    for name in ("max_periods", "max_periods_after_nonperiodic"):
        if getattr(args, name) < 2:
            ap.error(f"`--{name.replace('_', '-')}` = {getattr(args, name)} is not allowed: must be >= 2")
    MAP_SETTINGS.update(max_periods=args.max_periods, max_periods_after_nonperiodic=args.max_periods_after_nonperiodic)
    if args.quick:
        args.map_sizes, args.long_periods, args.ivp_periods, args.map_repeats = [40], 10_000, 50, 1
        args.batch_points = 400
    out = run(args)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(out, indent=1, sort_keys=True) + "\n")
    print(summary(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
