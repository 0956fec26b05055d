"""Shared helpers for the tests: the equations of motion written out again from the paper
(eqs. 2 and 9 of Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100), independent of
the library's matrices, and the physical checks every trajectory must pass."""

from __future__ import annotations

import ast
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

import impactdamper as idp
from impactdamper.reporting.readme import RESULTS_HEADER

REF = idp.Parameters()


def mck(p: idp.Parameters) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mass, damping and stiffness matrices of eqs. (2)/(9), for (x1, x2)."""
    mass = np.diag([p.m1, p.m2])
    damping = np.array([[p.k1 + p.k2, -p.k2], [-p.k2, p.k2]])
    stiffness = np.array([[p.c1 + p.c2, -p.c2], [-p.c2, p.c2]])
    return mass, damping, stiffness


def free_rhs(p: idp.Parameters):
    """y' for y = (x1, x2, x1', x2'), eqs. (2) and (9) with P0 sin(omega t) on the object."""

    def f(t, y):
        x1, x2, v1, v2 = y
        a1 = (p.P0 * np.sin(p.omega * t) - p.k1 * v1 - p.k2 * (v1 - v2) - p.c1 * x1 - p.c2 * (x1 - x2)) / p.m1
        a2 = (-p.k2 * (v2 - v1) - p.c2 * (x2 - x1)) / p.m2
        return np.array([v1, v2, a1, a2])

    return f


def stuck_rhs(p: idp.Parameters):
    """y' for the joined bodies y = (x1, x1'): (m1 + m2) x1'' + k1 x1' + c1 x1 = P0 sin(omega t)."""
    m = p.m1 + p.m2

    def f(t, y):
        return np.array([y[1], (p.P0 * np.sin(p.omega * t) - p.k1 * y[1] - p.c1 * y[0]) / m])

    return f


def contact_force(p: idp.Parameters, t, x1, v1):
    """F = -m2 x1'' - c2 Delta0 of the joined bodies."""
    m = p.m1 + p.m2
    a = (p.P0 * np.sin(p.omega * t) - p.k1 * v1 - p.c1 * x1) / m
    return -p.m2 * a - p.c2 * p.Delta0


def gap(p: idp.Parameters, full) -> np.ndarray:
    full = np.asarray(full)
    return p.Delta0 - (full[..., 1] - full[..., 0])


def energy(p: idp.Parameters, full) -> float:
    x1, x2, v1, v2 = full
    return 0.5 * (p.m1 * v1**2 + p.m2 * v2**2 + p.c1 * x1**2 + p.c2 * (x2 - x1) ** 2)


def phase_difference(a: float, b: float) -> float:
    """a - b on the circle of phases (units of T), in [-0.5, 0.5)."""
    return (a - b + 0.5) % 1.0 - 0.5


def check_impact_laws(p: idp.Parameters, events, gap_tol: float = 1e-12) -> int:
    """Every impact: on the stop, relative velocity -> -R times itself, momentum kept, energy
    not raised; every stick keeps momentum. Returns the number of impacts checked."""
    vscale = p.x_st * max(p.omega, p.omega1, p.omega2)
    n = 0
    for e in events:
        b, a = e.before, e.after
        pscale = (p.m1 + p.m2) * max(vscale, abs(b[2]), abs(b[3]))
        assert abs(p.m1 * a[2] + p.m2 * a[3] - p.m1 * b[2] - p.m2 * b[3]) <= 1e-13 * pscale, e
        assert np.array_equal(a[:2], b[:2]), e
        assert abs(gap(p, b)) <= gap_tol * p.x_st + 1e-15 * max(abs(b[0]), abs(b[1]), p.x_st), e
        escale = energy(p, b) + p.m1 * vscale**2
        assert energy(p, a) <= energy(p, b) + 1e-13 * escale, e
        if e.kind == "impact":
            n += 1
            v_before, v_after = b[3] - b[2], a[3] - a[2]
            assert v_before >= -1e-14 * vscale, e  # closing (or grazing)
            assert math.isclose(e.velocity, max(v_before, 0.0), rel_tol=1e-13, abs_tol=1e-14 * vscale)
            rounding = 1e-14 * max(np.max(np.abs(b[2:])), np.max(np.abs(a[2:])))  # v's are differences
            assert abs(v_after + p.R * v_before) <= 1e-13 * abs(v_before) + rounding, e
            S = p.m1 * p.m2 / (p.m1 + p.m2) * (1 + p.R) * max(v_before, 0.0)
            assert math.isclose(e.impulse, S, rel_tol=1e-13, abs_tol=1e-15 * p.m1 * vscale)
            if p.R == 1.0:
                assert math.isclose(energy(p, a), energy(p, b), rel_tol=1e-12, abs_tol=1e-13 * escale)
        elif e.kind == "stick":
            assert a[2] == a[3], e  # one common velocity
        else:
            assert e.kind == "liftoff", e
            assert np.array_equal(a, b)
            assert abs(contact_force(p, e.t, b[0], b[2])) <= 1e-10 * p.m2 * vscale * max(p.omega, p.omega1, p.omega2)
    return n


def check_no_penetration(
    p: idp.Parameters, traj, t0: float, t1: float, per_period: int = 400, gap_tol: float = 1e-12
) -> float:
    """Dense samples of the trajectory (plus points next to every event): the gap never goes
    below -gap_tol x_st; in contact, the contact force is non-negative. Returns the min gap."""
    n = max(int(per_period * (t1 - t0) / p.T), 16)
    ts = [np.linspace(t0, t1, n + 1)]
    ev = np.array([e.t for e in traj.events if t0 <= e.t <= t1])
    for d in (1e-9, 1e-6, 1e-3):
        ts.append(np.clip(ev + d * p.T, t0, t1))
        ts.append(np.clip(ev - d * p.T, t0, t1))
    ts = np.sort(np.concatenate(ts))
    full, modes = traj.sample(ts)
    g = gap(p, full)
    scale = np.maximum(np.abs(full[:, :2]).max(axis=1), p.x_st)
    assert np.all(g >= -gap_tol * p.x_st - 4e-16 * scale), float(g.min())
    stuck = modes == "stuck"
    if stuck.any():
        F = contact_force(p, ts[stuck], full[stuck, 0], full[stuck, 2])
        fscale = p.m2 * p.x_st * max(p.omega, p.omega1, p.omega2) ** 2
        assert np.all(F >= -1e-9 * fscale), float(F.min())
        assert np.all(np.abs(g[stuck]) <= 4e-16 * scale[stuck])
    return float(g.min())


# The library's modules (every .py file of src/impactdamper but the command line, the cli/
# package and __main__.py, which the package does not import and no rule runs).
_SRC = Path(__file__).resolve().parents[1] / "src" / "impactdamper"
_ROOT = _SRC.parents[1]
LIBRARY = sorted(
    str(p.relative_to(_ROOT))
    for p in _SRC.rglob("*.py")
    if p.name != "__main__.py" and p.relative_to(_SRC).parts[0] != "cli"
)


def _module_file(name: str):
    """The file of library module ``name`` (dotted, from ``impactdamper``), or None."""
    parts = name.split(".")
    if parts[0] != "impactdamper":
        return None
    base = _SRC.joinpath(*parts[1:])
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def library_imports(path) -> list[str]:
    """The library files that running ``path`` (a script or module) imports, followed through
    the library's own imports (and the workflow scripts it imports), at any depth and inside
    functions too, with the ``__init__.py``
    of every package on the way: what a rule running the script must list as inputs so that a
    change to them reruns it (Snakemake does not follow imports). Paths relative to the
    repository, sorted. A module a registry names as a string ``"impactdamper.x.y:NAME"``
    (core/backends.REGISTRY: the compiled backend, imported on first use) counts as imported."""
    import ast
    import re

    seen, todo = set(), [Path(path).resolve()]
    while todo:
        f = todo.pop()
        for node in ast.walk(ast.parse(f.read_text())):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Constant) and isinstance(node.value, str):
                names = re.findall(r"^(impactdamper(?:\.\w+)+):\w+$", node.value)
            for name in names:
                sibling = f.parent / f"{name}.py"  # another workflow script it imports
                if f.parent != _SRC and "." not in name and sibling.is_file() and sibling not in seen:
                    seen.add(sibling)
                    todo.append(sibling)
                parts = name.split(".")
                for i in range(1, len(parts) + 1):  # the packages on the way are imported too
                    target = _module_file(".".join(parts[:i]))
                    if target is not None and target not in seen:
                        seen.add(target)
                        todo.append(target)
    return sorted(str(p.relative_to(_ROOT)) for p in seen if _SRC in p.parents)


def library_parts(files) -> set[str]:
    """The parts of the library that ``files`` belong to, as the workflow's rules list them
    (workflow/rules/common.smk): a subpackage (``core``, ``reporting``, ...), one study module
    (``studies/claims/search``, ``studies/config``: each study is listed on its own, with the
    ``__init__`` of its room) or the package's ``__init__``."""
    out = set()
    for f in files:
        parts = Path(f).relative_to("src/impactdamper").parts
        if len(parts) == 1:
            out.add(parts[0])
        elif parts[0] == "studies":
            out.add(str(Path(*parts).with_suffix("")))
        else:
            out.add(parts[0])
    return out


def shipped_config(name: str = "config.yaml") -> dict:
    """A shipped config as a run sees it: config/config.yaml, with config/``name`` merged over it
    key by key as Snakemake merges a ``--configfile`` (config/ci.yaml holds only what differs)."""
    import copy

    import yaml
    from snakemake.utils import update_config

    config = yaml.safe_load((_ROOT / "config" / "config.yaml").read_text())
    if name != "config.yaml":
        config = copy.deepcopy(config)
        update_config(config, yaml.safe_load((_ROOT / "config" / name).read_text()))
    return config


# What a light start must not load: the heavy dependencies, which the solvers import on first use.
HEAVY_PACKAGES = ("scipy", "numba", "mpmath")


def heavy_modules_after(statement: str, also: tuple[str, ...] = ()) -> list[str]:
    """The modules of HEAVY_PACKAGES, and those starting with one of ``also``, that a fresh
    interpreter has loaded after running ``statement``."""
    code = (
        f"import sys; {statement}; "
        f"print(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY_PACKAGES!r} "
        f"or m.startswith({tuple(also)!r})))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return ast.literal_eval(out.stdout)


def parse_results_table(text: str) -> list[dict[str, str]]:
    """The rows of the first results table in ``text`` (Markdown), each a dict by column name:
    the inverse of :func:`impactdamper.reporting.readme.results_table`, for the README's test."""
    lines = [ln for ln in text.splitlines() if ln.startswith("|")]
    if not lines or [c.strip() for c in lines[0].strip("|").split(" | ")] != list(RESULTS_HEADER):
        raise ValueError("`text` holds no results table")
    out = []
    for ln in lines[2:]:
        cells = [c.strip().replace("\\|", "|") for c in ln.strip().strip("|").split(" | ")]
        out.append(dict(zip(RESULTS_HEADER, cells)))
    return out
