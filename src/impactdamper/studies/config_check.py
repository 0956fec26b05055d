"""The workflow's config checked before Snakemake plans a job: one line naming the key.

The Snakefile reads ``config/config.yaml`` (and any ``--configfile`` merged over it, and
``--config`` values) and hands it here before Snakemake's own ``validate`` fills in the
schema's defaults (``workflow/rules/common.smk``, :func:`check`). A value the workflow cannot
use stops the run at once, dry runs included, with one line ``Error validating config file:
['section']['key']: <why> is not allowed: <what is>`` and no schema dump, instead of failing in a
job minutes later or being read as something else. In order:

1. the files themselves (:func:`file_problem`): a key given twice, or a plain scalar that YAML
   1.1 (which Snakemake reads files with) reads otherwise than written (``010`` as 8);
2. the values typed as the schema expects (:func:`typed`: Snakemake hands ``--config`` values
   over as strings);
3. unknown keys (with the nearest known one), NaN and inf, the schema's own checks (its best
   error), ranges out of order (:data:`CONFIG_ORDER`), a claims map of a parameter against
   itself, the output root (:func:`output_root_problem`);
4. what the jobs' library calls would refuse (:func:`impactdamper.studies.config.config_problem`:
   the parameter sets, the settle options, the chunk counts);
5. the work the grids imply (:func:`grid_sizes`, at most :data:`MAX_LINE_POINTS` and the other
   bounds below: a step of 1e-9 is refused like 1e9 points) and the reference theta on the
   design chart's theta grid.
"""

from __future__ import annotations

import copy
import difflib
import math
import re
from collections.abc import Iterator
from pathlib import Path, PurePosixPath

import numpy as np

from impactdamper.analysis.response import MAX_POINTS
from impactdamper.core.simulate import MAX_SIMULATE_PERIODS

__all__ = [
    "ConfigError",
    "read_schema",
    "typed",
    "file_problem",
    "problem",
    "check",
    "output_root_problem",
    "grid_sizes",
    "CONFIG_ORDER",
    "MAX_LINE_POINTS",
    "MAX_CLOSED_FORM_POINTS",
    "MAX_MAP_CELLS",
    "MAX_SETTLED_POINTS",
    "MAX_STEPS",
    "MAX_REPEATS",
]

# Bounds on the points a grid implies (not on its raw key: a step of 1e-9 makes as many points
# as points: 1e9). Each is several times the full config's largest such grid, so that a finer
# study fits, and well below what would run for days or exhaust memory; a library limit where
# the job has one (the theta grids' MAX_POINTS, simulate's MAX_SIMULATE_PERIODS).
MAX_LINE_POINTS = 10_000  # settled motions along one line (full config: 1001 sweep values, 2004 random starts)
MAX_CLOSED_FORM_POINTS = 1_000_000  # Algorithm No. 1 values (closed form; full config: 2001) or linear curves
MAX_MAP_CELLS = 1_000_000  # cells of a regime map, by the compiled batch (full config: 400 x 400)
# Settled motions of a grid in two or more parameters, each run on its own (a claims map's cells
# to 1000 periods each, a design chart's, the nearest set's ray points; full config: 9552 ray points).
MAX_SETTLED_POINTS = 100_000
MAX_STEPS = 100_000_000  # a fixed-step run's steps (full config: 2e6)
MAX_REPEATS = 1_000  # timed repeats of one measurement (full config: 15)

# Pairs of config keys (low, high, strict) that must be ordered wherever both occur: the ends of
# a range (a reversed sweep or scan window used to fail only at run time), the continuation's
# steps, and a branch's seed within its bounds.
CONFIG_ORDER = [
    ("start", "stop", True),
    ("theta_start", "theta_stop", True),
    ("gap_start", "gap_stop", True),
    ("x_start", "x_stop", True),
    ("y_start", "y_stop", True),
    ("gap_min", "gap_max", True),
    ("gap_min", "gap", False),
    ("gap", "gap_max", False),
    ("min_step", "step", False),
    ("step", "max_step", False),
    ("max_periods_after_nonperiodic", "max_periods", False),
]

# A number as written in the config: decimal, with an optional fraction, exponent and digit
# groups (1_000); no leading zero (YAML 1.1 reads 010 as octal 8, YAML 1.2 as 10), no 0x/0o/0b
# prefix and no base-60 1:30 (YAML 1.1's 90). Anything else where a number is expected is
# refused, naming the key, rather than read one way or the other.
DECIMAL = r"[-+]?((0|[1-9][\d_]*)(\.[\d_]*)?|\.\d[\d_]*)([eE][-+]?\d+)?"
NOT_FINITE = r"[-+]?\.(inf|Inf|INF|nan|NaN|NAN)"
BOOLEANS = {"true": True, "True": True, "TRUE": True, "false": False, "False": False, "FALSE": False}

# Where a run's outputs may go besides the record ("."): the git-ignored scratch results/.
SCRATCH = "results"

Problem = tuple[tuple, str]  # (the key's path in the config, ": <why>")


class ConfigError(ValueError):
    """A config the workflow cannot use; the message is one line naming the key."""


def read_schema(path) -> dict:
    """The config's JSON schema (``workflow/schemas/config.schema.yaml``) as a dict."""
    import yaml

    return yaml.safe_load(Path(path).read_text())


def _schema_node(schema: dict, root: dict) -> dict:
    """A schema node with its $ref (#/definitions/...) followed."""
    while isinstance(schema, dict) and "$ref" in schema:
        target = root
        for part in schema["$ref"].lstrip("#/").split("/"):
            target = target[part]
        schema = {**target, **{k: v for k, v in schema.items() if k != "$ref"}}
    return schema if isinstance(schema, dict) else {}


def _types(schema: dict) -> list[str]:
    types = schema.get("type", [])
    return [types] if isinstance(types, str) else list(types)


def typed(node, schema: dict, root: dict | None = None):
    """The config with its values read as the types the schema expects.

    Snakemake hands the values of a nested --config dict over as strings, and PyYAML (YAML 1.1)
    reads a float without a dot, 1e-12 or 1e12, as a string. Where the schema expects a number
    or an integer, a string is read as a YAML scalar or, failing that, as a number in any float
    form (so --config reference='{theta: 1.1, ...}' and 1e-12 are typed like 1.0e-12 in the
    file; an integral float where an integer is expected becomes an int). Where it expects a
    string, a string stays one: a quoted 'yes' is not True. Anything else is left as it is, for
    :func:`problem` to judge.
    """
    root = schema if root is None else root
    schema = _schema_node(schema, root)
    if isinstance(node, dict):
        properties = schema.get("properties", {})
        return {key: typed(value, properties.get(key, {}), root) for key, value in node.items()}
    if isinstance(node, list):
        return [typed(value, schema.get("items", {}), root) for value in node]
    types = _types(schema)
    if not isinstance(node, str) or "string" in types:
        return node
    text = node.strip()
    if "boolean" in types:
        # YAML 1.2's booleans only: YAML 1.1's yes/no/on/off are strings (the schema names the key).
        return BOOLEANS.get(text, node)
    if "number" in types or "integer" in types:
        if re.fullmatch(NOT_FINITE, text):
            return float(text.replace(".", "", 1))  # (refused by problem(): must be finite)
        if not re.fullmatch(DECIMAL, text):
            return node  # not a decimal number (010, 0x10, 1:30 ...): problem() names the key
        if re.fullmatch(r"[-+]?[\d_]+", text):
            return int(text.replace("_", ""))
        value = float(text.replace("_", ""))
        return int(value) if "integer" in types and value.is_integer() else value
    return node


def _yaml11_only(text: str) -> str | None:
    """Why a plain scalar that YAML 1.1 reads as a number or a boolean is not one as written
    (its YAML 1.1 value, which YAML 1.2 reads otherwise), or None."""
    import yaml

    value = yaml.safe_load(text)
    if isinstance(value, bool):
        return None if text in BOOLEANS else f"YAML 1.1 reads it as {value}, YAML 1.2 as a string; write true or false"
    if isinstance(value, (int, float)):
        if re.fullmatch(DECIMAL, text) or re.fullmatch(NOT_FINITE, text):
            return None
        return f"YAML 1.1 reads it as {value!r}; write the number in decimal"
    return None


def file_problem(path) -> Problem | None:
    """The first key given twice (YAML loaders keep the last one silently) or plain number or
    boolean that YAML 1.1 reads differently from what is written (010 as 8, 1:30 as 90, 0x10 as
    16, on as True) in config file ``path``, read node by node; None if there is none or the
    file cannot be read or parsed (Snakemake reports that)."""
    import yaml

    try:
        root = yaml.compose(Path(path).read_text(), Loader=yaml.SafeLoader)
    except (OSError, yaml.YAMLError):
        return None
    return _node_problem(root, ())


def _node_problem(node, path: tuple) -> Problem | None:
    import yaml

    if isinstance(node, yaml.MappingNode):
        seen = set()
        for key_node, value_node in node.value:
            key = key_node.value
            if key in seen:
                return path + (key,), " is given twice: each key once (a YAML loader keeps the last one)"
            seen.add(key)
            found = _node_problem(value_node, path + (key,))
            if found is not None:
                return found
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            found = _node_problem(item, path + (i,))
            if found is not None:
                return found
    elif isinstance(node, yaml.ScalarNode) and node.style is None:
        why = _yaml11_only(node.value)
        if why is not None:
            return path, f": {node.value} is not allowed: {why}"
    return None


def _unknown_or_not_finite(node, schema: dict, root: dict, path: tuple) -> Problem | None:
    """The first unknown key (with the nearest known one), NaN/inf, or a string that YAML 1.1
    alone reads as a number or boolean where the schema expects one."""
    schema = _schema_node(schema, root)
    if isinstance(node, dict):
        properties = schema.get("properties", {})
        for key, value in node.items():
            if key not in properties and schema.get("additionalProperties") is False:
                near = difflib.get_close_matches(str(key), list(properties), n=1, cutoff=0.6)
                hint = f"did you mean {near[0]!r}?" if near else "allowed are " + ", ".join(properties)
                return path + (key,), f" is not a config key: {hint}"
            found = _unknown_or_not_finite(value, properties.get(key, {}), root, path + (key,))
            if found is not None:
                return found
    elif isinstance(node, list):
        for i, value in enumerate(node):
            found = _unknown_or_not_finite(value, schema.get("items", {}), root, path + (i,))
            if found is not None:
                return found
    elif isinstance(node, float) and not math.isfinite(node):
        return path, f": {node!r} is not allowed: must be a finite number"
    elif isinstance(node, str) and node.strip():
        types = _types(schema)
        if {"number", "integer", "boolean"} & set(types) and "string" not in types:
            why = _yaml11_only(node.strip())
            if why is not None:
                return path, f": {node.strip()} is not allowed: {why}"
    return None


def _schema_error(config: dict, schema: dict) -> Problem | None:
    """The schema's best error, in one short line."""
    import jsonschema

    error = jsonschema.exceptions.best_match(jsonschema.validators.validator_for(schema)(schema).iter_errors(config))
    if error is None:
        return None
    message = " ".join(error.message.split())
    return tuple(error.absolute_path), ": " + (message if len(message) <= 200 else message[:200] + "...")


def _disordered(node, path: tuple = ()) -> Problem | None:
    """The first pair of :data:`CONFIG_ORDER` keys out of order, anywhere in the config."""
    if isinstance(node, dict):
        for low, high, strict in CONFIG_ORDER:
            a, b = node.get(low), node.get(high)
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (a, b)):
                if (a >= b) if strict else (a > b):
                    return path, f": {low} = {a!r} is not allowed: must be {'<' if strict else '<='} {high} = {b!r}"
        items = node.items()
    elif isinstance(node, list):
        items = enumerate(node)
    else:
        return None
    for key, value in items:
        found = _disordered(value, path + (key,))
        if found is not None:
            return found
    return None


def _claims_maps(config: dict) -> Iterator[tuple[tuple, dict]]:
    """(path, section) of the claims map and of every pair map."""
    search = config.get("claims_search", {})
    if isinstance(search.get("map"), dict):
        yield ("claims_search", "map"), search["map"]
    for name, section in search.get("pair_maps", {}).items():
        if isinstance(section, dict):
            yield ("claims_search", "pair_maps", name), section


def _map_against_itself(config: dict) -> Problem | None:
    """A claims map whose y axis is its x axis (a map of gap against gap is a line)."""
    for path, section in _claims_maps(config):
        x, y = section.get("x"), section.get("y")
        if x is not None and x == y:
            return path + ("y",), f": {y!r} is not allowed: must differ from x = {x!r} (a map of two parameters)"
    return None


def output_root_problem(root) -> Problem | None:
    """Whether ``root`` (config ``output_root``) may hold a run's outputs: ``"."`` (the
    repository itself, the committed record) or a relative path under ``results/`` (the
    git-ignored scratch), such as ``results/ci``. Refused: ``/`` and every absolute path, a path
    that leaves the checkout (``..``), ``results/`` itself, and any other directory of the
    repository (the record in figures/ and paper/, the sources). Judged on the path as written,
    so that the check writes nothing and needs no file system."""
    allowed = f"must be '.' or a relative path under {SCRATCH}/ (the git-ignored scratch), such as {SCRATCH}/ci"
    if not isinstance(root, str) or not root.strip():
        return ("output_root",), f": {root!r} is not allowed: {allowed}"
    path = PurePosixPath(root)
    if path.parts == ():
        return None  # "." (or "./"): the record run
    if path.is_absolute() or ".." in path.parts or path.parts[0] != SCRATCH or len(path.parts) < 2:
        return ("output_root",), f": {root!r} is not allowed: {allowed}"
    # Resolved too (the run writes where its symbolic links lead): a link under results/ to a
    # directory outside the repository's scratch passed the check as written.
    scratch = Path.cwd().resolve() / SCRATCH
    resolved = Path(root).resolve()
    if resolved == scratch or not resolved.is_relative_to(scratch):
        return ("output_root",), f": {root!r} is not allowed: it resolves to {resolved} (a symbolic link); {allowed}"
    return None


def _with_defaults(config: dict, schema: dict) -> dict:
    """The config with the schema's defaults filled in where a key is missing (as Snakemake's
    validate does afterwards), for the checks of what the values make together."""
    import jsonschema

    filled = copy.deepcopy(config)
    validator = jsonschema.validators.validator_for(schema)

    def set_defaults(validator_, properties, instance, schema_):
        if isinstance(instance, dict):
            for key, sub in properties.items():
                if "default" in sub:
                    instance.setdefault(key, copy.deepcopy(sub["default"]))
        yield from validator.VALIDATORS["properties"](validator_, properties, instance, schema_)

    extended = jsonschema.validators.extend(validator, {"properties": set_defaults})
    for _ in extended(schema).iter_errors(filled):
        pass
    return filled


def _steps(start: float, stop: float, step: float) -> float:
    """Points of a grid from ``start`` to ``stop`` in steps of ``step`` (both ends included)."""
    return math.floor((stop - start) / step + 1e-9) + 1


def _key(section: dict, path: tuple, limit: int, what: str, count=None) -> tuple:
    """A grid set by one key: (path, its value, the points it implies (the value itself by
    default), limit, what)."""
    value = section[path[-1]]
    return path, repr(value), value if count is None else count, limit, what


def _product(path: tuple, names: str, counts: tuple, limit: int, what: str) -> tuple:
    """A grid of several keys' product: (path of their section, "a x b = 3 x 4", product, ...)."""
    shown = f"{names} = {' x '.join(str(c) for c in counts)}"
    return path, shown, math.prod(counts), limit, what


def grid_sizes(config: dict) -> list[tuple[tuple, str, float, int, str]]:
    """Every grid of a (schema-valid, defaults filled) config with the points it implies.

    Returns
    -------
    list of (path, shown, count, limit, what): the key that sets the grid (its path in the
    config; a section's for a product of keys) and its value as a message shows it (``1e-09``,
    ``points x gap_points = 400 x 400``), the number of points, cells or runs it implies, the
    most allowed, and what they are.
    """
    grids = []
    v = config.get("verdict")
    if v:
        scan = "gap values from gap_min to gap_max"
        for key, limit, what in (
            ("gap_step", MAX_LINE_POINTS, "Algorithm No. 2"),
            ("alg1_gap_step", MAX_CLOSED_FORM_POINTS, "Algorithm No. 1"),
        ):
            grids.append(_key(v, ("verdict", key), limit, f"{what} {scan}", _steps(v["gap_min"], v["gap_max"], v[key])))
        grids.append(
            _key(v, ("verdict", "R_step"), MAX_LINE_POINTS, "R values in [0, 1]", _steps(0.0, 1.0, v["R_step"]))
        )
        grids.append(_key(v, ("verdict", "random_states"), MAX_LINE_POINTS, "runs from random states"))
    s = config.get("sweep")
    if s:
        grids.append(_key(s, ("sweep", "points"), MAX_LINE_POINTS, "sweep values"))
        counts = (-(-s["points"] // s["random_every"]), s["random_starts"])
        grids.append(
            _product(
                ("sweep",), "ceil(points / random_every) x random_starts", counts, MAX_LINE_POINTS, "random starts"
            )
        )
    for name, m in config.get("maps", {}).items():
        if isinstance(m, dict):
            counts = (m["points"], m["gap_points"])
            grids.append(_product(("maps", name), "points x gap_points", counts, MAX_MAP_CELLS, "map cells"))
            grids.append(_key(m, ("maps", name, "points"), MAX_LINE_POINTS, "map rows"))
            grids.append(_key(m, ("maps", name, "gap_points"), MAX_LINE_POINTS, "map columns"))
    search = config.get("claims_search", {})
    for name, r in search.get("parameters", {}).items():
        path = ("claims_search", "parameters", name)
        grids.append(_key(r, path + ("points",), MAX_LINE_POINTS, "Algorithm No. 2 values"))
        grids.append(_key(r, path + ("alg1_points",), MAX_CLOSED_FORM_POINTS, "Algorithm No. 1 values"))
    for path, m in _claims_maps(config):
        counts = (m["x_points"], m["y_points"])
        grids.append(_product(path, "x_points x y_points", counts, MAX_SETTLED_POINTS, "map cells"))
        grids.append(_key(m, path + ("x_points",), MAX_LINE_POINTS, "map columns"))
        grids.append(_key(m, path + ("y_points",), MAX_LINE_POINTS, "map rows"))
    near = search.get("nearest")
    if near:
        # The rays: the 14 axes, 84 diagonals and `rays` random directions, each stepped to ray_max.
        counts = (98 + near["rays"], math.ceil(near["ray_max"] / near["ray_step"] - 1e-9))
        path = ("claims_search", "nearest")
        grids.append(_product(path, "(98 + rays) x ceil(ray_max / ray_step)", counts, MAX_SETTLED_POINTS, "ray points"))
        grids.append(_key(near, path + ("ball_points",), MAX_LINE_POINTS, "points on the ball"))
    if config.get("design"):
        grids += _design_grids(config["design"])
    perf = config.get("performance")
    if perf:
        path = ("performance",)
        grids.append(_key(perf, path + ("max_steps",), MAX_STEPS, "steps of a fixed-step run"))
        for i, n in enumerate(perf["growth_periods"]):
            grids.append((path + ("growth_periods", i), repr(n), n, MAX_SIMULATE_PERIODS, "simulated periods"))
        grids.append(_key(perf, path + ("settled_periods",), MAX_SIMULATE_PERIODS, "simulated periods"))
        grids.append(_key(perf, path + ("n_impacts",), MAX_LINE_POINTS, "impacts"))
        for i, n in enumerate(perf["compiled_speed_map_sizes"]):
            grids.append((path + ("compiled_speed_map_sizes", i), repr(n), n * n, MAX_MAP_CELLS, "map cells (n x n)"))
        grids.append(_key(perf, path + ("compiled_speed_batch_points",), MAX_MAP_CELLS, "batch points"))
        repeats = ("repeats", "reference_speed_repeats", "reference_speed_ivp_repeats", "compiled_speed_repeats")
        for key in (*repeats, "compiled_speed_map_repeats"):
            grids.append(_key(perf, path + (key,), MAX_REPEATS, "timed repeats"))
    if config.get("lyapunov"):
        grids += _lyapunov_grids(config["lyapunov"])
    if config.get("orbits"):
        from impactdamper.analysis.continuation import MAX_BRANCH_POINTS

        path = ("orbits", "continuation", "max_points")
        grids.append(_key(config["orbits"]["continuation"], path, MAX_BRANCH_POINTS, "orbits per leg"))
    return grids


def _lyapunov_grids(ly: dict) -> list[tuple[tuple, str, float, int, str]]:
    """The Lyapunov stage's grids (see :func:`grid_sizes`): the map's cells, rows and columns,
    and every run's length (transient, warm-up and averaged periods together, a run's work)."""
    m, path = ly["map"], ("lyapunov",)
    counts = (m["points"], m["gap_points"])
    grids = [
        _product(path + ("map",), "points x gap_points", counts, MAX_MAP_CELLS, "map cells"),
        _key(m, path + ("map", "points"), MAX_LINE_POINTS, "map rows"),
        _key(m, path + ("map", "gap_points"), MAX_LINE_POINTS, "map columns"),
    ]
    for names in (("transient", "warmup", "periods"), ("transient", "classify_warmup", "classify_periods")):
        counts = [ly[n] for n in names]
        shown = f"{' + '.join(names)} = {' + '.join(str(c) for c in counts)}"
        grids.append((path, shown, sum(counts), MAX_SIMULATE_PERIODS, "periods of a run"))
    grids.append(_key(ly, path + ("speed_repeats",), MAX_REPEATS, "timed repeats"))
    return grids


def _design_grids(d: dict) -> list[tuple[tuple, str, float, int, str]]:
    """The design stage's grids (see :func:`grid_sizes`)."""
    band = "theta values of the band"
    grids = [_key(d, ("design", "response_points"), MAX_POINTS, band)]
    n = math.ceil((d["theta_stop"] - d["theta_start"]) / d["band_step"] - 1e-9) + 1
    grids.append(_key(d, ("design", "band_step"), MAX_POINTS, band, n))
    grids.append(_key(d, ("design", "baseline_points"), MAX_CLOSED_FORM_POINTS, "theta values of the linear curves"))
    grids += [_key(d, ("design", key), MAX_LINE_POINTS, "gap values") for key in ("gap_points", "second_gap_points")]
    counts = (d["gap_points"], n)
    grids.append(_product(("design",), "gap_points x band points", counts, MAX_SETTLED_POINTS, "chart points"))
    counts = (len(d["second_values"]), d["second_gap_points"], n)
    names = "second_values x second_gap_points x band points"
    grids.append(_product(("design",), names, counts, MAX_SETTLED_POINTS, "chart points"))
    for key in ("search_samples", "search_polls", "search_polish", "robust_polls", "robust_polish", "search_checks"):
        grids.append(_key(d, ("design", key), MAX_LINE_POINTS, "evaluations"))
    grids.append(_key(d, ("design", "search_starts"), MAX_REPEATS, "searches"))
    grids.append(_key(d, ("design", "benchmark_objects"), MAX_REPEATS, "timed objects", len(d["benchmark_objects"])))
    return grids


def _too_large(config: dict) -> Problem | None:
    """The first grid of :func:`grid_sizes` above its bound."""
    for path, shown, count, limit, what in grid_sizes(config):
        if count > limit:
            many = f"{count:.3g}" if count >= 1e12 else f"{int(count)}"
            return path, f": {shown} is not allowed: {many} {what}; at most {limit}"
    return None


def _reference_theta_off_the_design_grid(config: dict) -> Problem | None:
    """The design chart reads each gap at the reference theta too: it must be a point of the
    chart's theta grid (steps of at most ``band_step`` from ``theta_start`` to ``theta_stop``),
    within the 1e-9 relative the chart's job allows (workflow/scripts/design_chart.py)."""
    d = config.get("design")
    if not d:
        return None
    theta = float(config["reference"]["theta"])
    a, b, step = float(d["theta_start"]), float(d["theta_stop"]), float(d["band_step"])

    def on_grid(s: float) -> bool:
        from impactdamper.analysis.peaks import band_points

        points = band_points([(a, b)], s)
        return bool(np.any(np.abs(np.linspace(a, b, points) - theta) <= 1e-9 * max(abs(theta), 1.0)))

    if on_grid(step):
        return None
    if not a <= theta <= b:
        return ("design",), (
            f": theta_start = {a!r}, theta_stop = {b!r} is not allowed: the band must contain the reference "
            f"theta = {theta:g} (the chart reads each gap there)"
        )
    fits = [s for s in (0.05, 0.025, 0.02, 0.01, 0.005) if on_grid(s)][:3]
    hint = f" (such as {', '.join(map(str, fits))})" if fits else ""
    return ("design", "band_step"), (
        f": {step!r} is not allowed: the theta grid from {a:g} to {b:g} must contain the reference theta = {theta:g}{hint}"
    )


def problem(config: dict, schema: dict) -> Problem | None:
    """The first problem of a (typed) config, in the order of the module's list, or None.

    Returns
    -------
    (path, message): the key's path in the config and ": <why>" (or " is ..." after a key).
    """
    from impactdamper.studies.config import config_problem

    for check_one in (
        lambda c: _unknown_or_not_finite(c, schema, schema, ()),
        lambda c: _schema_error(c, schema),
        _disordered,
        _map_against_itself,
        lambda c: output_root_problem(c["output_root"]) if "output_root" in c else None,
    ):
        found = check_one(config)
        if found is not None:
            return found
    filled = _with_defaults(config, schema)
    from impactdamper.studies.config_physics import design_object_out_of_range, elastic_on_a_preload

    for check_one in (
        elastic_on_a_preload,
        config_problem,
        _too_large,
        _reference_theta_off_the_design_grid,
        design_object_out_of_range,
    ):
        found = check_one(filled)
        if found is not None:
            return found
    return None


def _line(path: tuple, message: str, file=None) -> str:
    where = f" {file}" if file is not None else ""
    return f"Error validating config file{where}: " + "".join(f"[{p!r}]" for p in path) + message


def check(config: dict, schema: dict, files=()) -> dict:
    """The config typed as the schema expects, or :class:`ConfigError` with one line naming the key.

    Parameters
    ----------
    config : dict
        The config as Snakemake read it (the files merged, ``--config`` values as strings).
    schema : dict
        The config's JSON schema (:func:`read_schema`).
    files : iterable of path
        The config files of the run, each checked as written (:func:`file_problem`).
    """
    for file in files:
        found = file_problem(file)
        if found is not None:
            raise ConfigError(_line(*found, file=file))
    config = typed(config, schema)
    found = problem(config, schema)
    if found is not None:
        raise ConfigError(_line(*found))
    return config
