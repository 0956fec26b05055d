"""Helpers shared by the performance stage's scripts (issue 6): logging, JSON without
non-finite numbers, and LaTeX formatting of numbers for the generated macros and tables.

Timings are benchmark data: they depend on the machine and its load, so the files holding
them (listed in ``figures/nondeterministic.json``) are not compared by the figure record.
"""

import json
import logging
import math
from pathlib import Path

import numpy as np

from impactdamper import Parameters


def logger(log_path, name: str) -> logging.Logger:
    """A logger writing progress lines to the rule's log file."""
    Path(log_path).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(log_path, mode="w")
    handler.setFormatter(logging.Formatter("%(message)s"))
    lg = logging.getLogger(name)
    lg.handlers[:] = [handler]
    lg.setLevel(logging.INFO)
    lg.propagate = False
    return lg


def parameters(d: dict) -> Parameters:
    return Parameters(**{k: float(v) for k, v in d.items()})


def clean(obj):
    """JSON-ready copy: numpy scalars to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean(v) for v in obj]
    if isinstance(obj, (np.floating, float)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.ndarray):
        return clean(obj.tolist())
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


def write_json(path, obj) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(json.dumps(clean(obj), indent=1, sort_keys=True) + "\n")


def read_json(path) -> dict:
    return json.loads(Path(path).read_text())


def num(x) -> float:
    """A JSON number (None for not reached) back to float (inf)."""
    return math.inf if x is None else float(x)


def tex_sci(x: float, digits: int = 2) -> str:
    """x as LaTeX math, e.g. 3.1\\times10^{-14}; inf as 'not reached'."""
    if x is None or not math.isfinite(x):
        return r"\text{---}"
    if x == 0:
        return "0"
    e = math.floor(math.log10(abs(x)))
    m = x / 10**e
    if round(m, digits - 1) >= 10:
        m, e = m / 10, e + 1
    return rf"{m:.{digits - 1}f}\times10^{{{e}}}"


def tex_time(seconds: float) -> str:
    """A CPU time with a unit suited to its size (text mode), '---' when not reached."""
    if seconds is None or not math.isfinite(seconds):
        return "---"
    if seconds < 1e-3:
        return rf"{seconds * 1e6:.0f}\,\textmu s"
    if seconds < 1.0:
        return rf"{seconds * 1e3:.3g}\,ms"
    return rf"{seconds:.3g}\,s"


def tex_escape(text: str) -> str:
    """Escape LaTeX specials outside $...$ (math passes through)."""
    out, math_mode = [], False
    for ch in text:
        if ch == "$":
            math_mode = not math_mode
            out.append(ch)
        elif not math_mode and ch in "&%#_":
            out.append("\\" + ch)
        elif not math_mode and ch == "^":
            out.append(r"\textasciicircum{}")
        else:
            out.append(ch)
    return "".join(out)


def macro(name: str, value) -> str:
    return rf"\newcommand{{\{name}}}{{{value}}}"
