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
   over as strings); steps 1 and 2 are the reading of :mod:`impactdamper.studies.config_reading`;
3. unknown keys (with the nearest known one), NaN and inf, the schema's own checks (its best
   error), ranges out of order (:data:`CONFIG_ORDER`), a claims map of a parameter against
   itself, the output root (:func:`output_root_problem`);
4. what the jobs' library calls would refuse (:func:`impactdamper.studies.config.config_problem`:
   the parameter sets, the settle options, the chunk counts);
5. the work the grids imply (:func:`grid_sizes`, at most :data:`~impactdamper.studies.config_grids.MAX_LINE_POINTS`
   and the other bounds of :mod:`impactdamper.studies.config_grids`: a step of 1e-9 is refused like 1e9
   points) and the reference theta on the design chart's theta grid.
"""

from __future__ import annotations

import copy
import difflib
import math
from pathlib import Path, PurePosixPath

import numpy as np

from impactdamper.studies.config_grids import (
    claims_maps,
    grid_sizes,
    too_large,
)
from impactdamper.studies.config_reading import (
    Problem,
    file_problem,
    read_schema,
    schema_node,
    schema_types,
    typed,
    yaml11_only,
)

__all__ = [
    "ConfigError",
    "read_schema",
    "typed",
    "file_problem",
    "problem",
    "check",
    "grid_sizes",
    "CONFIG_ORDER",
]


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


# Where a run's outputs may go besides the record ("."): the git-ignored scratch results/.
SCRATCH = "results"


class ConfigError(ValueError):
    """A config the workflow cannot use; the message is one line naming the key."""


def _unknown_or_not_finite(node, schema: dict, root: dict, path: tuple) -> Problem | None:
    """The first unknown key (with the nearest known one), NaN/inf, or a string that YAML 1.1
    alone reads as a number or boolean where the schema expects one."""
    schema = schema_node(schema, root)
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
        types = schema_types(schema)
        if {"number", "integer", "boolean"} & set(types) and "string" not in types:
            why = yaml11_only(node.strip())
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


def _map_against_itself(config: dict) -> Problem | None:
    """A claims map whose y axis is its x axis (a map of gap against gap is a line)."""
    for path, section in claims_maps(config):
        x, y = section.get("x"), section.get("y")
        if x is not None and x == y:
            return path + ("y",), f": {y!r} is not allowed: must differ from x = {x!r} (a map of two parameters)"
    return None


def _output_root_problem(root) -> Problem | None:
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
        lambda c: _output_root_problem(c["output_root"]) if "output_root" in c else None,
    ):
        found = check_one(config)
        if found is not None:
            return found
    filled = _with_defaults(config, schema)
    from impactdamper.studies.config_physics import design_object_out_of_range, elastic_on_a_preload

    for check_one in (
        elastic_on_a_preload,
        config_problem,
        too_large,
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
