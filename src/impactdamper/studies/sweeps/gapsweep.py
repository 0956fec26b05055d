"""The sweeps stage's study: the gap Delta0/x_st swept over every regime of the reference case,
its grid, its tables' rows and the regime classes of the labels.

Extends Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100
(the paper computes one gap). The sweeps themselves are :mod:`impactdamper.analysis.sweeps`;
``workflow/scripts/sweep_*.py`` and ``map_*.py`` write the records.
"""

from __future__ import annotations

import numpy as np

from impactdamper.reporting.records import joined

__all__ = [
    "SWEEP_PARAMETER",
    "POINT_COLUMNS",
    "RANDOM_COLUMNS",
    "VELOCITY_FORMAT",
    "REGIMES_OF_LABELS",
    "regime_of_label",
    "runs",
    "grid",
    "map_axes",
    "point_row",
]

# The stage sweeps the gap Delta0/x_st (the library sweeps any parameter).
SWEEP_PARAMETER = "gap"
# Columns of the committed sweep table (figures/sweep_gap.csv): the state each point started
# from is kept at full precision so that any row can be recomputed on its own (tests).
POINT_COLUMNS = [
    "direction",
    "index",
    "value",
    "label",
    "regime",
    "k",
    "z",
    "stable",
    "multiplier",
    "x1_max",
    "contact_fraction",
    "method",
    "periods",
    "start",
    "x1_0",
    "x2_0",
    "v1_0",
    "v2_0",
    "velocities",
]
# What a table says of one settled point, wherever the point comes from.
SETTLED_COLUMNS = ["label", "regime", "k", "z", "x1_max", "method", "periods"]
RANDOM_COLUMNS = ["index", "start_index", "value", *SETTLED_COLUMNS, "velocities"]
# Digits of the impact velocities in the committed tables (plots need ~3); every other float
# has the records' 12 significant digits (a row recomputed from its start state agrees to
# ~1e-9, and the committed files stay small).
VELOCITY_FORMAT = "{:.4g}"
# The labels that name a class of their own (every other z/k label is an impact motion).
REGIMES_OF_LABELS = {
    "stuck": "stuck",
    "0/1": "no_contact",
    "np": "nonperiodic",
    "err": "failed",
    "1/1": "single_impact",
}


def regime_of_label(label: str) -> str:
    """The regime class of a label (inverse of impactdamper.analysis.point.label_of)."""
    if label in REGIMES_OF_LABELS:
        return REGIMES_OF_LABELS[label]
    return "chatter" if label.startswith("c/") else "multi_impact"


def runs(values, labels):
    """Runs of equal labels: list of (label, first value, last value, count)."""
    out = []
    for v, lab in zip(values, labels):
        if out and out[-1][0] == lab:
            out[-1][2], out[-1][3] = v, out[-1][3] + 1
        else:
            out.append([lab, v, v, 1])
    return [tuple(r) for r in out]


def grid(start: float, stop: float, points: int) -> np.ndarray:
    """The sweep grid: ``points`` values from start to stop inclusive."""
    return np.linspace(float(start), float(stop), int(points))


def map_axes(maps: dict, name: str) -> tuple:
    """(slow parameter, slow values, gap values) of regime map ``name`` of the config's
    ``maps`` section."""
    m = maps[name]
    return (
        m["parameter"],
        grid(m["start"], m["stop"], m["points"]),
        grid(m["gap_start"], m["gap_stop"], m["gap_points"]),
    )


def point_row(direction: str, index: int, pt) -> dict:
    """One row of the sweep table from a :class:`impactdamper.analysis.point.SweepPoint`."""
    r = pt.row()
    r.update(direction=direction, index=index, velocities=joined(pt.velocities, VELOCITY_FORMAT))
    return r


# --- the sweep's points as a record (npz) ---------------------------------------------------
# The transition bisection starts from the sweep's own points (their settled sections, cycles
# and Newton Jacobians), so they pass between the two rules whole, as plain arrays: one column
# per field of SweepPoint and direction, ragged fields flattened with their shapes.
_NONE_SHAPE = -1  # the shape row of a field that is None at a point


def _points_columns(points: list, prefix: str) -> dict:
    """The arrays of one direction's points (``prefix`` names the direction)."""
    from dataclasses import fields

    from impactdamper import Parameters

    out = {f"{prefix}/count": np.array(len(points))}
    names = Parameters.names()
    out[f"{prefix}/p"] = np.array([[float(getattr(pt.p, n)) for n in names] for pt in points]).reshape(
        len(points), len(names)
    )
    for f in fields(points[0]) if points else ():
        if f.name == "p":
            continue
        values = [getattr(pt, f.name) for pt in points]
        key = f"{prefix}/{f.name}"
        if all(v is None or isinstance(v, (bool, np.bool_)) for v in values):
            out[key + ".flag"] = np.array([-1 if v is None else int(v) for v in values], dtype=np.int8)
        elif all(isinstance(v, str) for v in values):
            out[key + ".str"] = np.array(values, dtype=str)
        elif all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in values):
            out[key + ".int"] = np.array(values, dtype=np.int64)
        elif all(isinstance(v, (float, np.floating)) for v in values):
            out[key + ".float"] = np.array(values, dtype=float)
        elif f.name == "cycle":
            for j, part in enumerate(("times", "states")):
                arrays = [np.asarray(v[j], dtype=float) if len(v) else None for v in values]
                out.update(_ragged(f"{key}.{part}", arrays))
        else:
            kind = "tuple" if all(isinstance(v, tuple) for v in values) else "array"
            arrays = [None if v is None else np.asarray(v, dtype=float) for v in values]
            out.update(_ragged(f"{key}.{kind}", arrays))
    return out


def _ragged(key: str, arrays: list) -> dict:
    """Arrays of any shape (or None) as one flat array and a shape table (rows padded with 0;
    the first column is the number of dimensions, -1 for None)."""
    ndim = max((a.ndim for a in arrays if a is not None), default=0)
    shapes = np.zeros((len(arrays), ndim + 1), dtype=np.int64)
    for i, a in enumerate(arrays):
        if a is None:
            shapes[i, 0] = _NONE_SHAPE
        else:
            shapes[i, 0] = a.ndim
            shapes[i, 1 : 1 + a.ndim] = a.shape
    flat = [a.ravel() for a in arrays if a is not None]
    return {key + ".flat": np.concatenate(flat) if flat else np.zeros(0), key + ".shape": shapes}


def _unragged(data, key: str) -> list:
    flat, shapes = data[key + ".flat"], data[key + ".shape"]
    out, at = [], 0
    for row in shapes:
        if row[0] == _NONE_SHAPE:
            out.append(None)
            continue
        shape = tuple(int(n) for n in row[1 : 1 + row[0]])
        size = int(np.prod(shape)) if shape else 1
        out.append(flat[at : at + size].reshape(shape))
        at += size
    return out


def write_points(path, points: dict) -> None:
    """The sweep's points (``{"up": [SweepPoint, ...], "down": [...]}``) as an npz record,
    read back by :func:`read_points` (no pickle: the file does not depend on where the class
    lives)."""
    from pathlib import Path

    arrays = {}
    for direction, pts in points.items():
        arrays.update(_points_columns(list(pts), direction))
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "wb") as f:
        np.savez(f, **arrays)


def read_points(path) -> dict:
    """The points written by :func:`write_points`, as ``{direction: [SweepPoint, ...]}``."""
    from dataclasses import fields

    from impactdamper import Parameters
    from impactdamper.analysis.point import SweepPoint

    with np.load(path, allow_pickle=False) as data:
        keys = list(data.keys())
        out = {}
        for direction in dict.fromkeys(k.split("/")[0] for k in keys):
            n = int(data[f"{direction}/count"])
            names = Parameters.names()
            columns = {"p": [Parameters(**dict(zip(names, (float(x) for x in row)))) for row in data[f"{direction}/p"]]}
            for f in fields(SweepPoint):
                key = f"{direction}/{f.name}"
                if f.name == "p":
                    continue
                if key + ".flag" in data:
                    columns[f.name] = [None if v < 0 else bool(v) for v in data[key + ".flag"]]
                elif key + ".str" in data:
                    columns[f.name] = [str(v) for v in data[key + ".str"]]
                elif key + ".int" in data:
                    columns[f.name] = [int(v) for v in data[key + ".int"]]
                elif key + ".float" in data:
                    columns[f.name] = [float(v) for v in data[key + ".float"]]
                elif key + ".times.flat" in data:
                    times, states = _unragged(data, key + ".times"), _unragged(data, key + ".states")
                    columns[f.name] = [() if t is None else (t, s) for t, s in zip(times, states)]
                elif key + ".tuple.flat" in data:
                    columns[f.name] = [
                        None if v is None else tuple(float(x) for x in v) for v in _unragged(data, key + ".tuple")
                    ]
                elif key + ".array.flat" in data:
                    columns[f.name] = _unragged(data, key + ".array")
                elif n:
                    raise ValueError(f"`path` = {str(path)!r} is not allowed: no field {f.name!r} of the points")
            out[direction] = [SweepPoint(**{name: col[i] for name, col in columns.items()}) for i in range(n)]
    return out
