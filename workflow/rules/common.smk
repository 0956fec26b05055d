# Shared helpers for every stage.
import json
import os
import sys
from pathlib import Path

import yaml

# The solver's matrices are 4 x 4: BLAS threads never help them, and on a loaded machine
# OpenBLAS's thread hand-offs slow the matrix-exponential path by up to ~90x (see
# tests/conftest.py). Every job inherits one BLAS thread (an explicit setting wins).
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")


# Jobs run in the environment that runs Snakemake (tools/setup.sh's .venv/): its bin/ goes first
# on PATH for shell commands (jupytext, python), and its Jupyter kernels first on JUPYTER_PATH,
# so that `.venv/bin/snakemake` works without activating the venv.
def prepend_to_search_path(name, directory):
    """Put ``directory`` first on the search path held in environment variable ``name``."""
    os.environ[name] = os.pathsep.join(p for p in [str(directory), os.environ.get(name, "")] if p)


for _name, _directory in (
    ("PATH", Path(sys.executable).parent),
    ("JUPYTER_PATH", Path(sys.prefix) / "share" / "jupyter"),
):
    prepend_to_search_path(_name, _directory)


# The library's source, part by part: every rule lists as inputs the parts its script imports
# (tests/helpers.py's library_imports follows the imports and tests/workflow checks every rule),
# so that a change reruns what it affects and nothing else (Snakemake does not follow Python
# imports by itself). The command line (cli.py, __main__.py) is no part: no rule runs it and
# the package does not import it.
def library_files(part):
    """The .py files of library part ``part``: a subpackage (``core``, with its own
    subpackages such as ``core/compiled``) or one module (``studies/claims/search``), paths
    relative to the repository."""
    path = Path("src/impactdamper", part)
    if path.with_suffix(".py").is_file():
        return [str(path.with_suffix(".py"))]
    return sorted(str(p) for p in path.rglob("*.py"))


CORE = library_files("core")
ANALYSIS = library_files("analysis")
BASELINES = library_files("baselines")
STUDIES = library_files("studies")
REPORTING = library_files("reporting")
# What importing anything of the library loads: the package's __init__.py imports the core and
# the periodic orbits of the analysis part.
PACKAGE = ["src/impactdamper/__init__.py"] + CORE + ANALYSIS


def study(*names):
    """The study modules ``names`` of the studies part, each a room's module (``claims/search``)
    or a shared one (``config``), with the modules it imports named too by the caller, and the
    ``__init__.py`` of the part and of every room named."""
    rooms = sorted({Path(n).parts[0] for n in names if len(Path(n).parts) > 1})
    inits = ["src/impactdamper/studies/__init__.py"] + [f"src/impactdamper/studies/{r}/__init__.py" for r in rooms]
    return inits + [f for n in names for f in library_files(f"studies/{n}")]


def library(*parts):
    """A rule's library inputs: the package (always loaded) and ``parts`` (lists of files), and
    the compiled kernels' warm-up (COMPILED_WARM_UP): the package imports the compiled solver,
    and a job that runs it must find numba's cache filled, not compile it beside other jobs. The
    warm-up orders the jobs but is no data: ancient(), so that a new warm-up (a scratch copy, a
    cluster run of one stage) does not rerun the jobs after it."""
    return sorted(set(PACKAGE).union(*parts)) + [ancient(COMPILED_WARM_UP)]


def library_sources(*parts):
    """library() without the warm-up: for rule compiled_warm_up itself."""
    return sorted(set(PACKAGE).union(*parts))


STYLE = ["src/impactdamper/reporting/plotting.py", "src/impactdamper/reporting/paper.mplstyle"]
ENV = "../../envs/impactdamper.yaml"

# Final products of each stage; rule all asks for all of them.
ALL_TARGETS = []

# The compiled kernels (core/compiled, numba) are compiled once, by rule compiled_warm_up
# (sweeps.smk), into numba's on-disk cache; every rule whose script runs compiled code lists this
# file as an input, so that parallel jobs load the cache (about 1 s) instead of each compiling
# (about 45 s).
COMPILED_WARM_UP = "results/compiled/warm_up.json"


def parameters_json(section="reference"):
    """The reference parameters as JSON, for a rule's params (reruns when they change)."""
    return json.dumps(config[section], sort_keys=True)


# Sweeps stage: the chunk files a gather rule waits for.
def map_chunk_files(wildcards, ext="csv"):
    """Chunk outputs of regime map `wildcards.map` (config maps.chunks jobs)."""
    return expand(
        "results/maps/{map}/chunk_{chunk}.{ext}",
        map=wildcards.map,
        chunk=range(config["maps"]["chunks"]),
        ext=ext,
    )


def map_chunk_timings(wildcards):
    return map_chunk_files(wildcards, ext="json")


def claims_map_chunk_files(wildcards):
    """Chunk outputs of the claims map (config claims_search.map.chunks jobs)."""
    return expand("results/claims/map_{chunk}.csv", chunk=range(config["claims_search"]["map"]["chunks"]))


def claims_pair_map_chunk_files(wildcards):
    """Chunk outputs of one pair map (config claims_search.pair_maps.{name}.chunks jobs)."""
    chunks = config["claims_search"]["pair_maps"][wildcards.name]["chunks"]
    return expand("results/claims/map_{name}_{chunk}.csv", name=wildcards.name, chunk=range(chunks))


def random_chunk_files(wildcards):
    """Chunk outputs of the random initial states (config sweep.random_chunks jobs)."""
    return expand("results/sweeps/random_{chunk}.csv", chunk=range(config["sweep"]["random_chunks"]))


def yaml_scalars(node, schema=None, root=None):
    """The config with its values read as the types the schema expects.

    Snakemake hands the values of a nested --config dict over as strings, and PyYAML (YAML 1.1)
    reads a float without a dot, 1e-12 or 1e12, as a string. Where the schema expects a number
    or an integer, a string is read as a YAML scalar or, failing that, as a number in any float
    form (so --config reference='{theta: 1.1, ...}' and 1e-12 are typed like 1.0e-12 in the
    file; an integral float where an integer is expected becomes an int). Where it expects a
    string, a string stays one: a quoted 'yes' is not True. Anything else is left as it is, for
    check_config and the schema to judge.
    """
    import re

    if root is None:
        root = schema = _config_schema()
    schema = _schema_node(schema, root)
    if isinstance(node, dict):
        properties = schema.get("properties", {})
        return {key: yaml_scalars(value, properties.get(key, {}), root) for key, value in node.items()}
    if isinstance(node, list):
        return [yaml_scalars(value, schema.get("items", {}), root) for value in node]
    types = schema.get("type", [])
    types = [types] if isinstance(types, str) else types
    if not isinstance(node, str) or "string" in types:
        return node
    if "boolean" in types:
        # YAML 1.2's booleans only: YAML 1.1's yes/no/on/off are strings (the schema names the key).
        text = node.strip()
        return True if text in ("true", "True", "TRUE") else False if text in ("false", "False", "FALSE") else node
    if "number" in types or "integer" in types:
        text = node.strip()
        if re.fullmatch(r"[-+]?\.(inf|Inf|INF|nan|NaN|NAN)", text):
            return yaml.safe_load(text)  # (named by check_config: must be finite)
        if not re.fullmatch(DECIMAL, text):
            return node  # not a decimal number (010, 0x10, 1:30 ...): check_config names the key
        if re.fullmatch(r"[-+]?[\d_]+", text):
            return int(text.replace("_", ""))
        value = float(text.replace("_", ""))
        if "integer" in types and value.is_integer():
            value = int(value)
        return value
    return node


# A number as written in the config: decimal, with an optional fraction, exponent and digit
# groups (1_000); no leading zero (YAML 1.1 reads 010 as octal 8, YAML 1.2 as 10), no 0x/0o/0b
# prefix and no base-60 1:30 (YAML 1.1's 90). Anything else where a number is expected is
# refused, naming the key, rather than read one way or the other.
DECIMAL = r"[-+]?((0|[1-9][\d_]*)(\.[\d_]*)?|\.\d[\d_]*)([eE][-+]?\d+)?"


def _yaml11_only(text):
    """Why a plain scalar that YAML 1.1 reads as a number or a boolean is not one as written
    (its YAML 1.1 value, which YAML 1.2 reads otherwise), or None."""
    import re

    value = yaml.safe_load(text)
    if isinstance(value, bool):
        ok = text in ("true", "True", "TRUE", "false", "False", "FALSE")
        return None if ok else f"YAML 1.1 reads it as {value}, YAML 1.2 as a string; write true or false"
    if isinstance(value, (int, float)):
        if re.fullmatch(DECIMAL, text) or re.fullmatch(r"[-+]?\.(inf|Inf|INF|nan|NaN|NAN)", text):
            return None
        return f"YAML 1.1 reads it as {value!r}; write the number in decimal"
    return None


def config_files():
    """The config files of this run: the workflow's own and those given with --configfile."""
    paths = list(workflow.configfiles) + list(workflow.overwrite_configfiles or [])
    return list(dict.fromkeys(str(p) for p in paths))


def check_config_files(paths):
    """Stop with one line naming the key if a config file repeats a key (YAML loaders keep the
    last one silently) or holds a plain number or boolean that YAML 1.1, which Snakemake reads
    files with, reads differently from what is written (010 as 8, 1:30 as 90, 0x10 as 16, on as
    True). The files themselves are read here again, node by node."""
    from snakemake.exceptions import WorkflowError

    for path in paths:
        try:
            root = yaml.compose(Path(path).read_text(), Loader=yaml.SafeLoader)
        except (OSError, yaml.YAMLError):
            continue  # Snakemake reports a file it cannot read or parse
        problem = _node_problem(root, ())
        if problem is not None:
            where, message = problem
            raise WorkflowError(f"Error validating config file {path}: " + "".join(f"[{p!r}]" for p in where) + message)


def _node_problem(node, path):
    """(path, message) of the first repeated key or YAML 1.1-only scalar under a YAML node."""
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


def _config_schema():
    """The config's JSON schema (workflow/schemas/config.schema.yaml) as a dict."""
    return yaml.safe_load(Path(workflow.basedir, "workflow", "schemas", "config.schema.yaml").read_text())


def _schema_node(schema, root):
    """A schema node with its $ref (#/definitions/...) followed."""
    while isinstance(schema, dict) and "$ref" in schema:
        target = root
        for part in schema["$ref"].lstrip("#/").split("/"):
            target = target[part]
        schema = {**target, **{k: v for k, v in schema.items() if k != "$ref"}}
    return schema if isinstance(schema, dict) else {}


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


def check_config(config):
    """Check the config and return it, or stop with one short line naming the key.

    Unknown keys at every level (a typo is named with the nearest known key), NaN and inf (which
    the schema's bounds let through: every comparison with NaN is false), the schema's own
    checks (its first error, not a dump of the schema), then reversed ranges (CONFIG_ORDER).
    Snakemake's validate runs after it, to fill in defaults.
    """
    import jsonschema
    from snakemake.exceptions import WorkflowError

    root = _config_schema()
    problem = _config_unknown_or_not_finite(config, root, root, ())
    if problem is None:
        error = jsonschema.exceptions.best_match(jsonschema.validators.validator_for(root)(root).iter_errors(config))
        if error is not None:
            message = " ".join(error.message.split())
            problem = (tuple(error.absolute_path), ": " + (message if len(message) <= 200 else message[:200] + "..."))
    if problem is None:
        problem = _config_disordered(config, ())
    if problem is None:
        # What the jobs' library calls would refuse (the reference case and the parameter sets
        # built from it, the settle options, the chunk counts), refused now with their message.
        from impactdamper.studies.config import config_problem

        problem = config_problem(_with_defaults(config, root))
    if problem is not None:
        path, message = problem
        # (Raised here, not deeper: Snakemake lists every workflow frame under the message.)
        raise WorkflowError("Error validating config file: " + "".join(f"[{p!r}]" for p in path) + message)
    return config


def _config_unknown_or_not_finite(node, schema, root, path):
    """(path, message) of the first unknown key or NaN/inf in the config, or None."""
    import difflib
    import math

    schema = _schema_node(schema, root)
    if isinstance(node, dict):
        properties = schema.get("properties", {})
        for key, value in node.items():
            if key not in properties and schema.get("additionalProperties") is False:
                near = difflib.get_close_matches(str(key), list(properties), n=1, cutoff=0.6)
                hint = f"did you mean {near[0]!r}?" if near else "allowed are " + ", ".join(properties)
                return path + (key,), f" is not a config key: {hint}"
            found = _config_unknown_or_not_finite(value, properties.get(key, {}), root, path + (key,))
            if found is not None:
                return found
    elif isinstance(node, list):
        for i, value in enumerate(node):
            found = _config_unknown_or_not_finite(value, schema.get("items", {}), root, path + (i,))
            if found is not None:
                return found
    elif isinstance(node, float) and not math.isfinite(node):
        return path, f": {node!r} is not allowed: must be a finite number"
    elif isinstance(node, str) and node.strip():
        types = schema.get("type", [])
        types = [types] if isinstance(types, str) else types
        if {"number", "integer", "boolean"} & set(types) and "string" not in types:
            why = _yaml11_only(node.strip())
            if why is not None:
                return path, f": {node.strip()} is not allowed: {why}"
    return None


def _with_defaults(config, schema):
    """The config with the schema's defaults filled in where a key is missing (as Snakemake's
    validate does afterwards), for the library's checks."""
    import copy

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


def _config_disordered(node, path):
    """(path, message) of the first pair of CONFIG_ORDER keys out of order, or None."""
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
        found = _config_disordered(value, path + (key,))
        if found is not None:
            return found
    return None
