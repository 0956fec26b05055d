"""The compiled solver's speed benchmark: its measurements against the pure-Python solver and DOP853.

The measurement functions of ``workflow/scripts/compiled_speed.py`` (which describes each one and
writes ``figures/compiled_speed.json``), on the paper's reference case (Timofeev et al. 2019,
Fig. 2): the solver's own runs and the regime maps here, what a user's calls cost in
:mod:`~impactdamper.studies.performance.front_door_speed`. The targets and the maps' settle
settings are arguments of :func:`run` (the workflow passes the config's); every timing is CPU
and wall time, with the 1-minute load average beside it
(:mod:`~impactdamper.studies.performance.timing`).
"""

from __future__ import annotations

import os
import platform
import statistics
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

import impactdamper as idp
from impactdamper.analysis.adaptive import adaptive_regime_map
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.sweeps import sweep, with_value
from impactdamper.baselines.ivp import simulate_ivp
from impactdamper.core.backends import warm_up
from impactdamper.core.compiled.layout import N_DIAG
from impactdamper.core.compiled.loop import count_kernel, pack_simulate_kernel, simulate_kernel
from impactdamper.core.compiled.pack import pack_parameters, packing_values
from impactdamper.core.settled_cycle import REGIMES
from impactdamper.studies.performance.compile_record import compile_times
from impactdamper.studies.performance.front_door_speed import front_door
from impactdamper.studies.performance.timing import load, strip, timed

RTOL = ATOL = 1e-10  # DOP853's tolerances named by the issue
# The full config's theta map (config/config.yaml, maps.theta); its settle settings (the
# SweepSettings fields settle_tol, max_periods, max_periods_after_nonperiodic,
# max_period_multiple) are the caller's: the workflow passes the config's maps section's.
MAP_GAPS = (-40.0, 15.0)
MAP_THETAS = (0.5, 1.5)
# Map points whose DOP853 cost is timed and extrapolated (a full DOP853 map would take hours).
IVP_MAP_SAMPLE = 6


def _count_events(p, t_end: float) -> int:
    """Events of the compiled run from Algorithm No. 2's step 1 to ``t_end``, unrecorded (the
    solver's pure cost per impact)."""
    pk = pack_parameters(p)
    err, n = count_kernel(pk.cm, pk.fm, pk.fc, pk.fk, pk.fg, pk.s, 0.0, idp.default_initial_state(p), float(t_end))
    if err or pk.fallback:
        raise RuntimeError(
            f"the compiled run failed (pack flag {pk.fallback}, error {err}): run simulate() for the message"
        )
    return int(n)


def _run_packing(p, t_end: float, pack=None):
    """The compiled run's arrays (flag, error, event kinds and values, segment modes and values)
    from step 1 to ``t_end``: the parameters packed in the same kernel call, or ``pack``."""
    full, diag = idp.default_initial_state(p), np.zeros(N_DIAG)
    if pack is None:
        v, tols, _ = packing_values(p)
        return pack_simulate_kernel(v, tols, 0.0, full, float(t_end), 256, diag)
    return (0,) + simulate_kernel(
        pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s, 0.0, full, float(t_end), 256, diag
    )


def phase_error(phase: float, reference: float) -> float:
    return abs((phase - reference + 0.5) % 1.0 - 0.5)


def per_impact(p, long_periods: int, ivp_periods: int, repeats: int, targets: dict) -> dict:
    n_events = _count_events(p, long_periods * p.T)
    traj = idp.simulate(p, long_periods * p.T, backend="compiled")
    impacts = len(traj.impacts())
    compiled = timed(lambda: _count_events(p, long_periods * p.T), repeats)
    # The public call on the same run (a Trajectory whose objects are made when first read).
    public = timed(lambda: idp.simulate(p, long_periods * p.T), repeats)
    short_ref = idp.simulate(p, ivp_periods * p.T, backend="python")
    short_impacts = len(short_ref.impacts())
    python = timed(lambda: idp.simulate(p, ivp_periods * p.T, backend="python"), max(1, repeats // 3))
    dop = timed(lambda: simulate_ivp(p, ivp_periods * p.T, method="DOP853", rtol=RTOL, atol=ATOL), 1)
    out = {
        "compiled": {
            **strip(compiled),
            "periods": long_periods,
            "events": n_events,
            "impacts": impacts,
            "us_per_impact_min": 1e6 * compiled["cpu_min_s"] / impacts,
            "us_per_impact_median": 1e6 * compiled["cpu_median_s"] / impacts,
        },
        "public_simulate": {
            **strip(public),
            "backend": public["result"].backend,
            "us_per_impact_min": 1e6 * public["cpu_min_s"] / impacts,
            "us_per_impact_median": 1e6 * public["cpu_median_s"] / impacts,
        },
        "python": {
            **strip(python),
            "periods": ivp_periods,
            "impacts": short_impacts,
            "us_per_impact_min": 1e6 * python["cpu_min_s"] / short_impacts,
        },
        "dop853": {
            **strip(dop),
            "periods": ivp_periods,
            "impacts": len(dop["result"].impacts()),
            "us_per_impact_min": 1e6 * dop["cpu_min_s"] / max(len(dop["result"].impacts()), 1),
        },
    }
    out["target_us"] = targets["us_per_impact"]
    out["met"] = out["compiled"]["us_per_impact_min"] <= targets["us_per_impact"]
    out["speedup_vs_python"] = out["python"]["us_per_impact_min"] / out["compiled"]["us_per_impact_min"]
    out["speedup_vs_dop853"] = out["dop853"]["us_per_impact_min"] / out["compiled"]["us_per_impact_min"]
    return out


def steady(p, repeats: int, targets: dict) -> dict:
    alg1 = idp.algorithm1(p)
    reference = alg1.impact_phase
    compiled = timed(lambda: idp.steady_state(p, backend="compiled"), repeats)
    s = compiled["result"]
    python = timed(lambda: idp.steady_state(p, backend="python"), max(1, repeats // 10))
    sp = python["result"]
    k = max(s.period_multiple, 1)
    t_span = (s.periods + k + 1) * p.T  # what steady_state simulates: settling, then one cycle and a period
    dop = timed(lambda: simulate_ivp(p, t_span, method="DOP853", rtol=RTOL, atol=ATOL), 2)
    pack = timed(lambda: pack_parameters(p), repeats)
    err_alg1 = phase_error(s.impacts[0].phase, reference)
    err_python = phase_error(s.impacts[0].phase, sp.impacts[0].phase)
    out = {
        "regime": s.regime,
        "periods": s.periods,
        "phase": s.impacts[0].phase,
        "phase_alg1": reference,
        "phase_error_vs_alg1": err_alg1,
        "phase_error_vs_python": err_python,
        "x1_max": s.x1_max,
        "x1_max_python": sp.x1_max,
        "simulated_periods": t_span / p.T,
        "compiled": strip(compiled),
        "packing_only": strip(pack),
        "python": strip(python),
        "dop853": strip(dop),
    }
    out["speedup_vs_dop853"] = dop["cpu_min_s"] / compiled["cpu_min_s"]
    out["speedup_vs_python"] = python["cpu_min_s"] / compiled["cpu_min_s"]
    out["targets"] = {
        "time_s": targets["steady_s"],
        "time_met": compiled["cpu_min_s"] <= targets["steady_s"],
        "speedup": targets["steady_speedup"],
        "speedup_met": out["speedup_vs_dop853"] >= targets["steady_speedup"],
        "phase": targets["phase"],
        "phase_met": max(err_alg1, err_python) <= targets["phase"],
    }
    return out


def first_impacts(p, repeats: int, targets: dict, count: int = 10) -> dict:
    ref = idp.simulate(p, 40 * p.T, backend="python")
    t_end = ref.impacts()[count - 1].t + 1e-6 * p.T  # just past the count-th impact
    compiled = timed(lambda: _run_packing(p, t_end), repeats)
    pack = pack_parameters(p)
    solver = timed(lambda: _run_packing(p, t_end, pack), repeats)
    objects = timed(lambda: idp.simulate(p, t_end, backend="compiled").events, repeats)
    python = timed(lambda: idp.simulate(p, t_end, backend="python"), max(1, repeats // 5))
    dop = timed(lambda: simulate_ivp(p, t_end, method="DOP853", rtol=RTOL, atol=ATOL), 3)
    (_, _, kinds, events, _, _), b = compiled["result"], python["result"]
    times = events[kinds == 0, 0]
    dt = float(np.max(np.abs(times - np.array([e.t for e in b.impacts()])))) / p.T
    out = {
        "impacts": count,
        "t_end_periods": t_end / p.T,
        "max_time_difference_vs_python_T": dt,
        "compiled": strip(compiled),
        "compiled_packed_once": strip(solver),
        "compiled_with_trajectory_objects": strip(objects),
        "python": strip(python),
        "dop853": strip(dop),
        "speedup_vs_dop853": dop["cpu_min_s"] / compiled["cpu_min_s"],
        "speedup_vs_python": python["cpu_min_s"] / compiled["cpu_min_s"],
    }
    out["speedup_vs_dop853_packed_once"] = dop["cpu_min_s"] / solver["cpu_min_s"]
    out["target_speedup"] = targets["first10_speedup"]
    out["met"] = out["speedup_vs_dop853"] >= targets["first10_speedup"]
    return out


def _map_rows(args) -> tuple[list, float, float, int]:
    """One worker's block of map rows (a chunk): (rows as dicts, cpu, wall, fallback points)."""
    thetas, gaps, rescue, map_settings = args
    c, w = time.process_time(), time.perf_counter()
    settings = SweepSettings(**map_settings, rescue=rescue)
    m = adaptive_regime_map(idp.Parameters(), "gap", gaps, "theta", thetas, settings=settings, brute_force=True)
    cpu, wall = time.process_time() - c, time.perf_counter() - w
    out = [
        {
            "regime": m.regime_code[r].tolist(),
            "k": m.period_multiple[r].tolist(),
            "z": m.impacts_per_cycle[r].tolist(),
            "periods": m.periods[r].tolist(),
            "fallback": int(np.count_nonzero(m.fallback[r] != "")),
        }
        for r in range(len(thetas))
    ]
    return out, cpu, wall, sum(o["fallback"] for o in out)


def _regime_map_timing(n: int, workers: int, repeats: int, rescue: bool, map_settings: dict) -> dict:
    gaps = np.linspace(*MAP_GAPS, n)
    thetas = np.linspace(*MAP_THETAS, n)
    # Rows dealt round-robin: the costly rows (near resonance, theta ~ 1) are contiguous, and a
    # contiguous split left one worker with most of them.
    blocks = [thetas[w::workers] for w in range(workers)]
    walls, cpus, result = [], [], None
    with ProcessPoolExecutor(workers) as pool:
        # Each worker loads the kernels first.
        list(pool.map(_map_rows, [(b[:1], gaps[:4], rescue, map_settings) for b in blocks]))
        for _ in range(repeats):
            w = time.perf_counter()
            result = list(pool.map(_map_rows, [(b, gaps, rescue, map_settings) for b in blocks]))
            walls.append(time.perf_counter() - w)
            cpus.append(sum(r[1] for r in result))
    worker_cpu = [r[1] for r in result]
    worker_wall = [r[2] for r in result]
    rows = [row for r in result for row in r[0]]
    codes = np.array([row["regime"] for row in rows])
    periods = np.array([row["periods"] for row in rows])
    regimes = {name: int(np.sum(codes == i)) for i, name in enumerate(REGIMES)}
    return (
        {
            "points": n * n,
            "grid": [n, n],
            "workers": workers,
            "rescue": rescue,
            "wall_min_s": min(walls),
            "wall_median_s": statistics.median(walls),
            "cpu_total_min_s": min(cpus),
            "load_1min": load(),
            "fallback_points": int(sum(r[3] for r in result)),
            "regimes": regimes,
            "worker_cpu_s": worker_cpu,
            "worker_wall_s": worker_wall,
            "simulated_periods": int(periods.sum()),
            "us_per_point": 1e6 * min(cpus) / (n * n),
        },
        periods,
        gaps,
        thetas,
    )


def _map_baselines(periods: np.ndarray, gaps: np.ndarray, thetas: np.ndarray, map_settings: dict) -> dict:
    """DOP853 on a sample of map points over their simulated periods, and one pure-Python row,
    each extrapolated to the whole map by simulated periods (rows)."""
    rng = np.random.default_rng(0)
    n = len(gaps)
    picks = rng.choice(n * n, IVP_MAP_SAMPLE, replace=False)
    cpu, sim = 0.0, 0
    for idx in picks:
        i, j = divmod(int(idx), n)
        p = idp.Parameters(theta=float(thetas[i]), gap=float(gaps[j]))
        c = time.process_time()
        try:
            simulate_ivp(p, int(periods[i, j]) * p.T, method="DOP853", rtol=RTOL, atol=ATOL)
        except RuntimeError:
            continue
        cpu += time.process_time() - c
        sim += int(periods[i, j])
    per_period = cpu / max(sim, 1)
    row = n // 2
    settings = SweepSettings(**map_settings, continuation=True)
    c = time.process_time()
    sweep(with_value(idp.Parameters(), "theta", float(thetas[row])), "gap", gaps, settings=settings)
    py_row = time.process_time() - c
    return {
        "dop853_sample_points": IVP_MAP_SAMPLE,
        "dop853_s_per_period": per_period,
        "dop853_map_estimate_s": per_period * float(periods.sum()),
        "python_row_cpu_s": py_row,
        "python_map_estimate_s": py_row * n,
        "load_1min": load(),
        "note": "estimates: DOP853 per simulated period on a random sample of map points times the map's "
        "simulated periods; the pure-Python regime_map (with its accelerators) on the middle row times "
        "the number of rows",
    }


def run_maps(targets: dict, map_settings: dict, *, map_repeats: int = 1, workers: int = 2, map_sizes=(200,)) -> dict:
    """The regime maps of the benchmark (``map_sizes``, n x n), each timed on ``workers``
    processes (``map_repeats`` times, without the rescue) and once more with the rescue: the
    part of the benchmark that needs the machine's cores to itself. Each map's ``periods`` (its
    cells' simulated periods, rows of theta) are kept for :func:`map_baselines`."""
    warm_up("compiled")
    maps = {}
    for n in map_sizes:
        m, periods, _, _ = _regime_map_timing(n, workers, map_repeats, rescue=False, map_settings=map_settings)
        # The same map with the batch's Newton rescue of the cells not settled within the cap
        # (impactdamper.steady_states' default): how many of them were slow transients.
        r, _, _, _ = _regime_map_timing(n, workers, 1, rescue=True, map_settings=map_settings)
        m["rescue_run"] = {
            "wall_s": r["wall_min_s"],
            "cpu_s": r["cpu_total_min_s"],
            "regimes": r["regimes"],
            "load_1min": r["load_1min"],
        }
        m["nonperiodic_share"] = m["regimes"].get("nonperiodic", 0) / m["points"]
        m["nonperiodic_share_rescued"] = r["regimes"].get("nonperiodic", 0) / m["points"]
        m["target_s"] = targets["map_s"] if n == 200 else None
        m["met"] = (m["wall_min_s"] <= targets["map_s"]) if n == 200 else None
        m["periods"] = periods.tolist()
        maps[f"{n}x{n}"] = m
    return maps


def run(
    targets: dict,
    map_settings: dict,
    *,
    repeats: int = 5,
    map_repeats: int = 1,
    long_periods: int = 10_000,
    ivp_periods: int = 200,
    workers: int = 2,
    map_sizes=(200,),
    batch_points: int = 10_000,
    compile_time: bool = True,
    maps: dict | None = None,
) -> dict:
    """Every measurement of the benchmark, against ``targets`` (the config's
    performance.compiled_speed_targets), the maps with ``map_settings`` (SweepSettings fields:
    the config's maps caps): the maps of :func:`run_maps` (``maps``, timed on their own where
    given) with their DOP853 and pure-Python estimates; ``compile_time=False`` leaves the
    record's 'compile' null (timed on its own by :func:`compile_times`)."""
    p = idp.Parameters()
    warm_up("compiled")
    out = {"case": p.to_dict(), "compile": compile_times() if compile_time else None}
    out["per_impact"] = per_impact(p, long_periods, ivp_periods, repeats, targets)
    out["steady_state"] = steady(p, repeats * 10, targets)
    out["first_10_impacts"] = first_impacts(p, repeats * 10, targets)
    out["front_door"] = front_door(p, repeats * 10, batch_points, targets, map_settings)
    if maps is None:
        maps = run_maps(targets, map_settings, map_repeats=map_repeats, workers=workers, map_sizes=map_sizes)
    maps = {name: dict(m) for name, m in maps.items()}
    for k, m in enumerate(maps.values()):
        periods = np.array(m.pop("periods"))
        if k == 0:
            n = len(periods)
            m["baselines"] = _map_baselines(
                periods, np.linspace(*MAP_GAPS, n), np.linspace(*MAP_THETAS, n), map_settings
            )
            m["speedup_vs_dop853_estimate"] = m["baselines"]["dop853_map_estimate_s"] / m["cpu_total_min_s"]
    out["maps"] = maps
    out["notes"] = [
        "maps run the batch entry point without the rescue (SweepSettings(rescue=False), the config's maps.rescue) "
        "for the timing; 'rescue_run' is the same map once with the rescue (the stroboscopic Newton from the "
        "kernels' last sections, impactdamper.steady_states' default): nonperiodic_share before, "
        "nonperiodic_share_rescued after",
        "the reference regime_map uses its accelerators (orbit continuation, stroboscopic Newton); the batch "
        "simulates every point (solve_point with continuation=False), as tests/unit/test_compiled.py checks",
        "first_10_impacts 'compiled' packs the parameter set in each call, in the same compiled call as the run "
        "(the free mode's eigen-decomposition by LAPACK's dgeev, numpy's eig bit for bit); 'compiled_packed_once' "
        "reuses the packed arrays, as a search over one parameter set would",
    ]
    out["machine"] = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": __import__("numba").__version__,
        "platform": platform.platform(),
        "cpu_count": os.cpu_count(),
        "load_1min_end": load(),
    }
    return out


def summary(out: dict) -> str:
    c, pi, st, f10 = out["compile"], out["per_impact"], out["steady_state"], out["first_10_impacts"]
    yes = {True: "met", False: "NOT met", None: "-"}
    lines = [
        f"JIT compile from scratch: {c['cold_compile_s']:.1f} s"
        if c
        else "JIT compile: timed on its own (compile_times)",
        f"JIT load from the cache:  {c['cached_load_s']:.2f} s" if c else "",
        f"per impact ({pi['compiled']['impacts']} impacts, load {pi['compiled']['load_1min']:.1f}): compiled "
        f"{pi['compiled']['us_per_impact_min']:.2f} us (median {pi['compiled']['us_per_impact_median']:.2f}; public "
        f"simulate {pi['public_simulate']['us_per_impact_median']:.2f} us median); "
        f"python {pi['python']['us_per_impact_min']:.1f} us; DOP853 {pi['dop853']['us_per_impact_min']:.0f} us; "
        f"target <= {pi['target_us']} us: {yes[pi['met']]}",
        f"steady state ({st['regime']}, {st['periods']} periods, load {st['compiled']['load_1min']:.1f}): compiled "
        f"{1e3 * st['compiled']['cpu_min_s']:.3f} ms (median {1e3 * st['compiled']['cpu_median_s']:.3f}; packing "
        f"{1e3 * st['packing_only']['cpu_min_s']:.3f}); python {1e3 * st['python']['cpu_min_s']:.1f} ms; DOP853 "
        f"{1e3 * st['dop853']['cpu_min_s']:.0f} ms: {st['speedup_vs_dop853']:.0f}x; phase error vs Alg. 1 "
        f"{st['phase_error_vs_alg1']:.1e} T, vs python {st['phase_error_vs_python']:.1e} T; targets <= 1 ms: "
        f"{yes[st['targets']['time_met']]}, >= 300x: {yes[st['targets']['speedup_met']]}, phase <= 1e-12 T: "
        f"{yes[st['targets']['phase_met']]}",
        f"first 10 impacts: compiled {1e3 * f10['compiled']['cpu_min_s']:.3f} ms (parameters packed once "
        f"{1e3 * f10['compiled_packed_once']['cpu_min_s']:.3f} ms, {f10['speedup_vs_dop853_packed_once']:.0f}x; "
        f"as a Trajectory "
        f"{1e3 * f10['compiled_with_trajectory_objects']['cpu_min_s']:.3f} ms); python "
        f"{1e3 * f10['python']['cpu_min_s']:.2f} ms; DOP853 {1e3 * f10['dop853']['cpu_min_s']:.1f} ms: "
        f"{f10['speedup_vs_dop853']:.0f}x (target >= 100x: {yes[f10['met']]}); times vs python "
        f"{f10['max_time_difference_vs_python_T']:.1e} T",
    ]
    fd = out["front_door"]
    lines.append(
        f"front door: impactdamper.steady_state(Parameters()) median {1e3 * fd['steady_state']['auto']['wall_median_s']:.3f} ms "
        f"({fd['steady_state']['backend']}; python backend {1e3 * fd['steady_state']['python']['wall_median_s']:.1f} ms, "
        f"{fd['steady_state']['speedup_vs_python']:.0f}x; target <= {1e3 * fd['steady_state']['target_s']:.1f} ms: "
        f"{yes[fd['steady_state']['met']]}); batch of {fd['batch']['points']} points "
        f"{fd['batch']['us_per_point_public']:.0f} us per point vs the kernels' {fd['batch']['us_per_point_kernel']:.0f} "
        f"us ({fd['batch']['ratio']:.2f}x; target <= {fd['batch']['target_ratio']}x: {yes[fd['batch']['met']]}); "
        f"CLI steady --json wall {fd['cli']['wall_median_s']:.2f} s median (import {fd['cli']['import_median_s']:.2f} s, "
        f"numba on import: {fd['cli']['import_loads_numba']}; target <= {fd['cli']['target_s']} s: {yes[fd['cli']['met']]})"
    )
    for name, m in out["maps"].items():
        line = (
            f"map {name} ({m['workers']} processes, rescue off, load {m['load_1min']:.1f}): wall "
            f"{m['wall_min_s']:.1f} s (median {m['wall_median_s']:.1f}), cpu {m['cpu_total_min_s']:.1f} s (per "
            f"worker {', '.join(f'{c:.1f}' for c in m['worker_cpu_s'])} s cpu, "
            f"{', '.join(f'{w:.1f}' for w in m['worker_wall_s'])} s wall), "
            f"{m['us_per_point']:.0f} us per point, {m['simulated_periods']} periods simulated; "
            f"nonperiodic {m['regimes'].get('nonperiodic', 0)} points ({100 * m['nonperiodic_share']:.1f} %; with the "
            f"rescue {100 * m['nonperiodic_share_rescued']:.1f} %, cpu {m['rescue_run']['cpu_s']:.1f} s)"
        )
        if m.get("target_s"):
            line += f"; target <= {m['target_s']:.0f} s: {yes[m['met']]}"
        if "baselines" in m:
            b = m["baselines"]
            line += (
                f"; DOP853 estimate {b['dop853_map_estimate_s']:.0f} s ({m['speedup_vs_dop853_estimate']:.0f}x), "
                f"python regime_map estimate {b['python_map_estimate_s']:.0f} s"
            )
        lines.append(line)
    return "\n".join(lines)
