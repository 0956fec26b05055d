"""Records a workflow stage writes and reads: CSV, JSON, the rule's log, timing.

Every writer is deterministic (fixed column and key order, fixed float format, ``\\n`` line
ends), so the same inputs give byte-identical files, and creates the parent folder.
"""

from __future__ import annotations

import csv
import json
import logging
import math
import os
import statistics
import time
from pathlib import Path

import numpy as np

from impactdamper.core.blas import one_blas_thread

__all__ = [
    "CSV_FLOAT",
    "BOOLEAN_CELLS",
    "clean",
    "write_json",
    "read_json",
    "json_float",
    "write_csv",
    "read_csv",
    "cell_float",
    "split_floats",
    "joined",
    "start_stage",
    "run_stage",
    "say",
    "machine",
    "Timer",
    "paired_cpu_ratios",
    "write_chunk",
    "JOB_COST_DIR",
    "job_name",
]

# Significant digits of floats in CSV records: far below any tolerance the record is compared
# with (rtol 1e-8), and it keeps the files small.
CSV_FLOAT = ".12g"


def clean(obj):
    """JSON-ready copy: numpy scalars and arrays to Python, non-finite floats to None, tuples
    to lists, keys to strings."""
    if isinstance(obj, dict):
        return {str(k): clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return clean(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(float(obj)) else None
    return obj


def write_json(path, obj, *, indent: int = 1, sort_keys: bool = True) -> None:
    """``obj`` (cleaned by :func:`clean`) as JSON with a final newline."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(clean(obj), indent=indent, sort_keys=sort_keys) + "\n")


def read_json(path):
    """A JSON record as Python objects."""
    return json.loads(Path(path).read_text())


def json_float(x) -> float:
    """A JSON number back to float; None (a value not reached, written by :func:`clean`) to inf."""
    return math.inf if x is None else float(x)


# How booleans are written in a CSV cell (``booleans=`` of :func:`write_csv`).
BOOLEAN_CELLS = {"words": ("false", "true"), "digits": ("0", "1"), "python": ("False", "True")}


def _csv_cell(value, *, booleans: str = "words", float_format: str | None = CSV_FLOAT) -> str:
    """One CSV cell: floats to ``float_format`` (non-finite and None empty; ``None``: Python's
    shortest round-trip form, ``nan`` and ``inf`` included, for the timing records), booleans
    as ``true``/``false`` (``booleans="words"``), ``1``/``0`` (``"digits"``) or
    ``True``/``False`` (``"python"``)."""
    if booleans not in BOOLEAN_CELLS:
        raise ValueError(f"`booleans` = {booleans!r} is not allowed: must be one of {', '.join(BOOLEAN_CELLS)}")
    if isinstance(value, (bool, np.bool_)):
        return BOOLEAN_CELLS[booleans][bool(value)]
    if isinstance(value, (float, np.floating)):
        if float_format is None:
            return repr(float(value))
        return format(float(value), float_format) if math.isfinite(float(value)) else ""
    if value is None:
        return ""
    return str(value)


def write_csv(path, columns, rows, *, booleans: str = "words", float_format: str | None = CSV_FLOAT) -> None:
    """CSV with a header row ``columns``; each row a dict (missing keys empty); cells by
    :func:`csv_cell`."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(list(columns))
        for row in rows:
            w.writerow([_csv_cell(row.get(c), booleans=booleans, float_format=float_format) for c in columns])


def read_csv(path) -> list[dict]:
    """Rows of a CSV record as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def cell_float(s) -> float:
    """A CSV cell as float (empty: nan)."""
    return float(s) if s not in ("", None) else math.nan


def split_floats(s: str) -> list[float]:
    """A ``;``-joined CSV cell back to floats."""
    return [float(x) for x in s.split(";")] if s else []


def joined(values, fmt: str = "{:.4g}") -> str:
    """Floats joined by ``;`` in one CSV cell."""
    return ";".join(fmt.format(float(v)) for v in values)


def _stage_logger(log_path, name: str, *, timestamps: bool = False, library: bool = False) -> logging.Logger:
    """A logger writing progress lines to the rule's log file. ``library=True`` also routes
    the library's own ``impactdamper`` logger there (sweeps report their progress)."""
    Path(log_path).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(log_path, mode="w")
    handler.setFormatter(
        logging.Formatter("%(asctime)s %(message)s", "%H:%M:%S") if timestamps else logging.Formatter("%(message)s")
    )
    for n in (name, "impactdamper") if library else (name,):
        lg = logging.getLogger(n)
        for old in lg.handlers:
            old.close()  # a second stage in one process (the tests) replaces the first's log
        lg.handlers[:] = [handler]
        lg.setLevel(logging.INFO)
        lg.propagate = False
    return logging.getLogger(name)


# Every workflow job's exact CPU time, written when its script ends (start_stage): Snakemake's
# benchmark samples a job's processes once a second and never sees a worker process that starts
# and ends between two samples (a pool of map_blocks or steady_states' workers), so the rules'
# cost (impactdamper.studies.performance.cost) takes the job's own count where there is one.
JOB_COST_DIR = "results/benchmarks/jobs"


def job_name(rule: str, wildcards: dict) -> str:
    """A job's name: its rule, then its wildcards' values in the order of their names, each after
    a ``-`` (the workflow's benchmark files are named so too)."""
    return rule + "".join(f"-{wildcards[k]}" for k in sorted(wildcards))


def _job_cpu_seconds() -> dict:
    """This process's CPU time and its waited-for children's (pools joined, subprocesses
    finished), user and system, s."""
    import resource

    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    self_s, children_s = own.ru_utime + own.ru_stime, children.ru_utime + children.ru_stime
    return {"cpu_s": self_s + children_s, "self_s": self_s, "children_s": children_s}


def _record_job_cost(rule: str, wildcards: dict, pid: int) -> None:
    if os.getpid() != pid:  # (a forked worker that exits through atexit: not the job)
        return
    path = Path(JOB_COST_DIR) / f"{job_name(rule, wildcards)}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({**_job_cpu_seconds(), "end": time.time()}) + "\n")


def start_stage(sm, name: str | None = None, *, timestamps: bool = False, library: bool = False):
    """The start of every workflow script that Snakemake runs (``script:``): where it logs, and
    the rule's ``params`` with the config sections (JSON strings, the workflow's
    ``parameters_json``) read back as dicts; one BLAS thread in the job
    (:mod:`impactdamper.core.blas`). A Snakemake job's exact CPU time (this process and its
    waited-for children) is written when the script ends, to ``JOB_COST_DIR/<job_name>.json``.

    Parameters
    ----------
    sm : snakemake.script.Snakemake
        The object Snakemake hands the script.
    name : str, optional
        The script's logger name: progress lines go to the rule's log through
        :func:`stage_logger` (``timestamps``, ``library`` as there). Without it, the script's
        standard error is the log.

    Returns
    -------
    params : dict
        Each of the rule's params by name; a string holding a JSON object is read as a dict.
    log : logging.Logger or None
        The logger, if ``name`` was given.
    """
    # One BLAS thread: Snakemake sets a job's BLAS thread counts to its threads, which the job
    # spends on worker processes instead (core/blas.py says why).
    one_blas_thread(force=True)
    log = None
    if name is None:
        import sys

        sys.stderr = open(sm.log[0], "w")  # noqa: SIM115 (open for the job's life)
    else:
        log = _stage_logger(sm.log[0], name, timestamps=timestamps, library=library)
    params = {}
    for key, value in sm.params.items():
        if isinstance(value, str) and value.startswith("{"):
            value = json.loads(value)
        params[key] = value
    if getattr(sm, "rule", None):  # a Snakemake job: its exact CPU time recorded when it ends
        import atexit

        atexit.register(_record_job_cost, sm.rule, dict(sm.wildcards.items()), os.getpid())
    return params, log


def say(message: str) -> None:
    """A progress line on the standard error (the rule's log, after :func:`start_stage`)."""
    import sys

    print(message, file=sys.stderr, flush=True)


def _job_value(view, spec: str):
    """One value of a Snakemake job: a path ``input.csv``, ``params.reference``, with ``?`` where
    it may be absent (None) and a conversion ``:int``, ``:float`` or ``:list``."""
    path, _, convert = spec.partition(":")
    value = view
    for part in path.split("."):
        value = getattr(value, part.rstrip("?"), None) if part.endswith("?") else getattr(value, part)
    return {"": lambda v: v, "int": int, "float": float, "list": list}[convert](value)


def run_stage(job, main, *args, logger: str | None = None, timestamps: bool = False, library: bool = False, **kwargs):
    """Run a workflow script's ``main`` as the Snakemake job ``job`` (the ``snakemake`` object the
    ``script:`` directive injects): the stage's start (:func:`start_stage`: its log, its params
    read back) and the call of ``main`` with each argument taken from the job.

    Parameters
    ----------
    job : snakemake.script.Snakemake
        The job.
    main : callable
        The script's ``main`` (which the tests call directly).
    args : str, callable, or a tuple of them
        ``main``'s arguments, in order: strings of whitespace-separated paths in the job
        (``"wildcards.case input.csv output.pdf"``; ``params.<name>`` is a config section read
        back as a dict, ``threads`` the job's, ``log`` the stage's logger, ``say`` a function of
        one progress line, to the logger or the standard error; ``?`` after a part: None where
        the job has none; a conversion ``:int``, ``:float`` or ``:list`` after a path; a
        keyword argument as ``name=path``), or a callable of the job's view (those attributes)
        for a value built from several.
    logger, timestamps, library
        The stage's logger name and options (:func:`start_stage`); without a name the script's
        standard error is the rule's log.
    kwargs : str or callable
        ``main``'s keyword arguments: one path each, or a callable as above.

    Returns
    -------
    What ``main`` returns.
    """
    import types

    params, log = start_stage(job, logger, timestamps=timestamps, library=library)
    view = types.SimpleNamespace(
        input=job.input,
        output=job.output,
        wildcards=job.wildcards,
        threads=job.threads,
        params=types.SimpleNamespace(**params),
        log=log,
        say=log.info if log is not None else say,
    )

    positional, keywords = [], {}
    for spec in [s for a in args for s in (a if isinstance(a, (tuple, list)) else [a])]:
        for token in [spec] if callable(spec) else spec.split():
            key, _, path = token.rpartition("=") if isinstance(token, str) else ("", "", token)
            value = path(view) if callable(path) else _job_value(view, path)
            if key:
                keywords[key] = value
            else:
                positional.append(value)
    keywords.update({key: spec(view) if callable(spec) else _job_value(view, spec) for key, spec in kwargs.items()})
    return main(*positional, **keywords)


def machine() -> dict:
    """What a timing ran on: processors and load (other jobs share the machine)."""
    return {"cpu_count": os.cpu_count(), "load_average": list(os.getloadavg())}


class Timer:
    """Wall and processor time of a block (processor time of this process only)."""

    def __enter__(self):
        self.wall0, self.cpu0, self.epoch0 = time.perf_counter(), time.process_time(), time.time()
        return self

    def __exit__(self, *exc):
        self.wall = time.perf_counter() - self.wall0
        self.cpu = time.process_time() - self.cpu0
        self.epoch1 = time.time()
        return False


def paired_cpu_ratios(base, other, repeats: int, clock=time.process_time) -> dict:
    """How many times ``other`` costs ``base``, measured in pairs: each call of ``other`` between
    two calls of ``base``, its CPU time over the mean of theirs, after one warm-up call of each.

    On a shared machine a process's CPU time per call moves with the load beside it (caches, the
    other hyperthread); two blocks timed one after the other can meet different loads (the
    reference-speed benchmark's ratio of two blocks' medians read 23.9 and 13.6 in two runs of
    the same code). A pair's calls are adjacent in time, so they meet the same load.

    Returns
    -------
    dict
        ``ratios`` (one per pair), ``median`` (their median), ``other_cpu_s`` and ``base_cpu_s``
        (the calls' times: one of ``other``, two of ``base`` per pair), ``result`` (``other``'s
        last result).
    """
    if not (isinstance(repeats, int) and not isinstance(repeats, bool) and repeats >= 1):
        raise ValueError(f"`repeats` = {repeats!r} is not allowed: must be an integer >= 1")

    def cpu(fn):
        start = clock()
        result = fn()
        return clock() - start, result

    base()
    result = other()
    ratios, other_times, base_times = [], [], []
    for _ in range(repeats):
        before, _ = cpu(base)
        spent, result = cpu(other)
        after, _ = cpu(base)
        ratios.append(spent / (0.5 * (before + after)))
        other_times.append(spent)
        base_times += [before, after]
    median = statistics.median(ratios)
    return {"ratios": ratios, "median": median, "other_cpu_s": other_times, "base_cpu_s": base_times, "result": result}


def write_chunk(
    out_csv, columns, rows, out_json, timer: Timer, /, *, epochs: bool = False, booleans: str = "words", **counts
):
    """The two records of a job that computes one chunk of a stage's rows: the rows (CSV, as
    :func:`write_csv`) and the chunk's timing (JSON: ``counts``, the :class:`Timer`'s wall and
    processor time, with ``epochs`` its start and end times, and the :func:`machine`). The
    records are positional only, so that a count may be named ``rows`` or ``columns``.

    Returns
    -------
    dict
        The timing record.
    """
    write_csv(out_csv, columns, rows, booleans=booleans)
    timing = {**counts, "wall_s": timer.wall, "cpu_s": timer.cpu, "machine": machine()}
    if epochs:
        timing.update(start_epoch=timer.epoch0, end_epoch=timer.epoch1)
    write_json(out_json, timing, indent=2)
    return timing
