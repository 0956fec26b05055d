"""Shared helpers of the sweeps stage (issue 5): settings from the config, grids, tables,
timing and logging.

Not a figure script. The stage's scripts import it (Snakemake puts ``workflow/scripts`` on
``sys.path`` for ``script:`` rules; the tests import the scripts by path). The paper is
Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100.
"""

import csv
import json
import logging
import math
import os
import time
from pathlib import Path

import numpy as np

from impactdamper import Parameters, Tolerances
from impactdamper.analysis.sweeps import SweepPoint, SweepSettings

# The stage sweeps the gap Delta0/x_st (the library sweeps any parameter).
SWEEP_PARAMETER = "gap"
PAPER = "Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100"
# Columns of the committed sweep table (figures/sweep_gap.csv): the state each point started
# from is kept at full precision so that any row can be recomputed on its own (tests).
POINT_COLUMNS = ["direction", "index", "value", "label", "regime", "k", "z", "stable", "multiplier", "x1_max",
                 "contact_fraction", "method", "periods", "start", "x1_0", "x2_0", "v1_0", "v2_0", "velocities"]
RANDOM_COLUMNS = ["index", "start_index", "value", "label", "regime", "k", "z", "x1_max", "method", "periods",
                  "velocities"]
# Digits of the impact velocities in the committed tables (plots need ~3), and of every other
# float (12 significant digits: a row recomputed from its start state agrees to ~1e-9, and the
# committed files stay small).
VELOCITY_FORMAT = "{:.4g}"
FLOAT_FORMAT = "{:.12g}"


# One colour per regime class in every sweep and map figure (labels z/k are written on them).
# Chosen so that classes that border each other stay apart in print, in greyscale and for
# red-green colour-blind readers (CIELAB distance >= 28 under simulated deuteranopia and
# protanopia for every bordering pair): np, which only says "not settled within the cap", is a
# pale cream, far from the orange of the z/k motions.
REGIME_COLORS = {
    "stuck": "#404040",         # persistent contact: dark grey
    "chatter": "#c994c7",       # contact phases reached by chatter: light purple
    "multi_impact": "#f0a830",  # several impacts or k > 1: orange
    "single_impact": "#1f4e79", # one impact per period: dark blue
    "no_contact": "#a6cee3",    # no contact: light blue
    "nonperiodic": "#fff2cc",   # not settled within the cap: pale cream
    "failed": "#ffffff",        # the simulation raised (label err): white
}
# Text written on a band or region of each class: white on the dark ones, black elsewhere.
REGIME_TEXT = {"stuck": "white", "single_impact": "white"}
REGIME_NAMES = {
    "stuck": "persistent contact (S)", "chatter": "chatter, c/k", "multi_impact": "z/k impacts",
    "single_impact": "1/1 (one impact)", "no_contact": "no contact (0/1)",
    "nonperiodic": "np: not settled within the cap",
    "failed": "solver failed (err)",
}


def regime_of_label(label: str) -> str:
    """The regime class of a label (inverse of impactdamper.analysis.sweeps.label_of)."""
    if label == "stuck":
        return "stuck"
    if label == "0/1":
        return "no_contact"
    if label == "np":
        return "nonperiodic"
    if label == "err":
        return "failed"
    if label.startswith("c/"):
        return "chatter"
    return "single_impact" if label == "1/1" else "multi_impact"


def runs(values, labels):
    """Runs of equal labels: list of (label, first value, last value, count)."""
    out = []
    for v, lab in zip(values, labels):
        if out and out[-1][0] == lab:
            out[-1][2], out[-1][3] = v, out[-1][3] + 1
        else:
            out.append([lab, v, v, 1])
    return [tuple(r) for r in out]


def located_gap(located_json) -> float:
    """The located case's Delta0/x_st from the reference stage (figures/located_case.json)."""
    return float(json.loads(Path(located_json).read_text())["located"]["gap"])


# --- config ---------------------------------------------------------------------------------
def parameters(d: dict) -> Parameters:
    """Parameters from a config-like dict holding every relative parameter."""
    return Parameters(**{name: float(d[name]) for name in Parameters.names()})


def tolerances(solver: dict) -> Tolerances:
    return Tolerances(gap_tol=float(solver["gap_tol"]), chatter_tol=float(solver["chatter_tol"]))


def settings(section: dict, solver: dict, **changes) -> SweepSettings:
    """SweepSettings from a ``sweep:`` or ``maps:`` config section and the ``solver:`` one."""
    kw = dict(
        settle_tol=float(section["settle_tol"]),
        max_periods=int(section["max_periods"]),
        max_periods_after_nonperiodic=int(section["max_periods_after_nonperiodic"]),
        max_period_multiple=int(section["max_period_multiple"]),
        tolerances=tolerances(solver),
    )
    kw.update(changes)
    return SweepSettings(**kw)


def grid(start: float, stop: float, points: int) -> np.ndarray:
    """The sweep grid: ``points`` values from start to stop inclusive."""
    return np.linspace(float(start), float(stop), int(points))


def chunk_indices(n: int, chunks: int, chunk: int) -> np.ndarray:
    """Indices of chunk ``chunk`` of ``chunks`` contiguous, near-equal blocks of range(n)."""
    if not (0 <= chunk < chunks):
        raise ValueError(f"`chunk` = {chunk!r} is not allowed: must be in [0, {chunks})")
    return np.array_split(np.arange(n), chunks)[chunk]


# --- tables ---------------------------------------------------------------------------------
def _fmt(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return "" if not math.isfinite(float(v)) else FLOAT_FORMAT.format(float(v))
    return str(v)


def joined(values, fmt: str = VELOCITY_FORMAT) -> str:
    return ";".join(fmt.format(float(v)) for v in values)


def point_row(direction: str, index: int, pt: SweepPoint) -> dict:
    r = pt.row()
    r.update(direction=direction, index=index, velocities=joined(pt.velocities))
    return r


def write_csv(path, rows: list[dict], columns: list[str]) -> None:
    """Deterministic CSV: fixed column order, floats to FLOAT_FORMAT, '\\n' line ends."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(columns)
        for r in rows:
            w.writerow([_fmt(r[c]) for c in columns])


def read_csv(path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(s: str) -> float:
    """A CSV cell as float (empty: nan)."""
    return float(s) if s not in ("", None) else math.nan


def split_floats(s: str) -> list[float]:
    return [float(x) for x in s.split(";")] if s else []


def write_json(path, obj) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(json.dumps(obj, indent=2, sort_keys=True) + "\n")


# --- logging and timing -------------------------------------------------------------------
def logger(log_path, name: str) -> logging.Logger:
    """A logger writing progress lines to the rule's log file (and the library's too)."""
    Path(log_path).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(log_path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(message)s", "%H:%M:%S"))
    for n in (name, "impactdamper"):
        lg = logging.getLogger(n)
        lg.handlers[:] = [handler]
        lg.setLevel(logging.INFO)
        lg.propagate = False
    return logging.getLogger(name)


def machine() -> dict:
    """What the timing ran on: processors and load (other jobs share this machine)."""
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
