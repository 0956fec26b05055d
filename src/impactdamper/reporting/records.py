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
import time
from pathlib import Path

import numpy as np

__all__ = [
    "CSV_FLOAT",
    "BOOLEAN_CELLS",
    "clean",
    "write_json",
    "read_json",
    "json_float",
    "csv_cell",
    "write_csv",
    "read_csv",
    "cell_float",
    "split_floats",
    "joined",
    "stage_logger",
    "start_stage",
    "machine",
    "Timer",
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


def csv_cell(value, *, booleans: str = "words", float_format: str | None = CSV_FLOAT) -> str:
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
            w.writerow([csv_cell(row.get(c), booleans=booleans, float_format=float_format) for c in columns])


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


def stage_logger(log_path, name: str, *, timestamps: bool = False, library: bool = False) -> logging.Logger:
    """A logger writing progress lines to the rule's log file. ``library=True`` also routes
    the library's own ``impactdamper`` logger there (sweeps report their progress)."""
    Path(log_path).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(log_path, mode="w")
    handler.setFormatter(
        logging.Formatter("%(asctime)s %(message)s", "%H:%M:%S") if timestamps else logging.Formatter("%(message)s")
    )
    for n in (name, "impactdamper") if library else (name,):
        lg = logging.getLogger(n)
        lg.handlers[:] = [handler]
        lg.setLevel(logging.INFO)
        lg.propagate = False
    return logging.getLogger(name)


def start_stage(sm, name: str | None = None, *, timestamps: bool = False, library: bool = False):
    """The start of every workflow script that Snakemake runs (``script:``): where it logs, and
    the rule's ``params`` with the config sections (JSON strings, the workflow's
    ``parameters_json``) read back as dicts.

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
    log = None
    if name is None:
        import sys

        sys.stderr = open(sm.log[0], "w")  # noqa: SIM115 (open for the job's life)
    else:
        log = stage_logger(sm.log[0], name, timestamps=timestamps, library=library)
    params = {}
    for key, value in sm.params.items():
        if isinstance(value, str) and value.startswith("{"):
            value = json.loads(value)
        params[key] = value
    return params, log


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
