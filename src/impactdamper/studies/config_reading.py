"""The workflow's config as read: its JSON schema, the values typed as the schema expects, and
the plain scalars YAML 1.1 reads otherwise than written.

Steps 1 and 2 of :mod:`impactdamper.studies.config_check`: Snakemake reads config files with
YAML 1.1 (``010`` is 8, ``on`` is True) and hands ``--config`` values over as strings, so a
value is read here as the schema's type says, and a file's plain scalar that YAML 1.1 alone
reads as a number or a boolean, or a key given twice, is named (:func:`file_problem`).
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["Problem", "read_schema", "schema_node", "schema_types", "typed", "yaml11_only", "file_problem"]

# A number as written in the config: decimal, with an optional fraction, exponent and digit
# groups (1_000); no leading zero (YAML 1.1 reads 010 as octal 8, YAML 1.2 as 10), no 0x/0o/0b
# prefix and no base-60 1:30 (YAML 1.1's 90). Anything else where a number is expected is
# refused, naming the key, rather than read one way or the other.
DECIMAL = r"[-+]?((0|[1-9][\d_]*)(\.[\d_]*)?|\.\d[\d_]*)([eE][-+]?\d+)?"
NOT_FINITE = r"[-+]?\.(inf|Inf|INF|nan|NaN|NAN)"
BOOLEANS = {"true": True, "True": True, "TRUE": True, "false": False, "False": False, "FALSE": False}

Problem = tuple[tuple, str]  # (the key's path in the config, ": <why>")


def read_schema(path) -> dict:
    """The config's JSON schema (``workflow/schemas/config.schema.yaml``) as a dict."""
    import yaml

    return yaml.safe_load(Path(path).read_text())


def schema_node(schema: dict, root: dict) -> dict:
    """A schema node with its $ref (#/definitions/...) followed."""
    while isinstance(schema, dict) and "$ref" in schema:
        target = root
        for part in schema["$ref"].lstrip("#/").split("/"):
            target = target[part]
        schema = {**target, **{k: v for k, v in schema.items() if k != "$ref"}}
    return schema if isinstance(schema, dict) else {}


def schema_types(schema: dict) -> list[str]:
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
    schema = schema_node(schema, root)
    if isinstance(node, dict):
        properties = schema.get("properties", {})
        return {key: typed(value, properties.get(key, {}), root) for key, value in node.items()}
    if isinstance(node, list):
        return [typed(value, schema.get("items", {}), root) for value in node]
    types = schema_types(schema)
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


def yaml11_only(text: str) -> str | None:
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
        why = yaml11_only(node.value)
        if why is not None:
            return path, f": {node.value} is not allowed: {why}"
    return None
