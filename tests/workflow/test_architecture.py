"""docs/ARCHITECTURE.md is true where a test can check it: the module table quotes modules that
exist (and every module of studies/ and reporting/), the public names it quotes are the
package's, its stage table quotes studies.STAGE_ROOMS and each stage's scripts use their room, the files that state
the impact law are the ones the source states it in, and a new parameter's plumbing is the
files that list the parameters. Beyond the page: every library file, workflow script and
library module the project's text names still exists."""

import ast
import functools
import re
from pathlib import Path

import pytest
from helpers import library_imports  # (what a script imports; tests/ is on pytest's pythonpath)

import impactdamper
from impactdamper.studies import STAGE_ROOMS

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src" / "impactdamper"
DOC = (ROOT / "docs" / "ARCHITECTURE.md").read_text()


# The page's section on the library: the modules it quotes (the registry is the source tree).
LIBRARY_SECTION = DOC.split("## The library, bottom up")[1].split("## The workflow")[0]


def test_modules_the_page_quotes_exist():
    """Every ``name.py`` the library section quotes is a module of the package."""
    modules = {p.name for p in SRC.rglob("*.py")}
    quoted = set(re.findall(r"`([\w]+\.py)`", LIBRARY_SECTION))
    assert len(quoted) > 50 and quoted <= modules, sorted(quoted - modules)


def test_the_page_quotes_every_study_and_reporting_module():
    for package in ("studies", "reporting"):
        modules = {p.name for p in (SRC / package).rglob("*.py") if p.name != "__init__.py"}
        assert len(modules) > 5, package  # (the glob found the tree)
        assert not [m for m in sorted(modules) if f"`{m}`" not in LIBRARY_SECTION], package


def test_public_names_quoted_are_the_packages():
    """Every ``impactdamper.<name>`` the page quotes is a public name of the package."""
    quoted = set(re.findall(r"`impactdamper\.(\w+)\(", DOC))
    assert {"simulate", "steady_state", "steady_states"} <= quoted
    assert quoted <= set(impactdamper.__all__), sorted(quoted - set(impactdamper.__all__))


def test_the_page_quotes_the_stage_rooms():
    """docs/ARCHITECTURE.md's stage table is studies.STAGE_ROOMS, row by row (a room's stages in
    the constant's order), and names every room."""
    rooms = {p.parent.name for p in (SRC / "studies").glob("*/__init__.py")}
    assert set(STAGE_ROOMS.values()) == rooms, sorted(set(STAGE_ROOMS.values()) ^ rooms)
    for room in rooms:
        stages = ", ".join(f"`{stage}.smk`" for stage, r in STAGE_ROOMS.items() if r == room)
        assert f"| {stages} | `{room}/` |" in DOC, (room, stages)
    assert DOC.count(".smk` | `") == len(rooms)  # (no other row)


@pytest.mark.slow  # follows every stage script's imports (about 25 s)
def test_each_stage_has_its_room_and_its_scripts_use_it():
    stages = STAGE_ROOMS
    rooms = set(stages.values())
    for stage, room in stages.items():
        rules = (ROOT / "workflow" / "rules" / f"{stage}.smk").read_text()
        scripts = set(re.findall(r'script="(workflow/scripts/\w+\.py)"', rules))
        imported = set().union(*(library_imports(ROOT / s) for s in scripts))
        assert any(f.startswith(f"src/impactdamper/studies/{room}/") for f in imported), (stage, room)
    # Every room module is imported by a script of its stages (or by a module of its room).
    for room in rooms:
        scripts = set()
        for stage in (s for s, r in stages.items() if r == room):
            rules = (ROOT / "workflow" / "rules" / f"{stage}.smk").read_text()
            scripts |= set(re.findall(r'script="(workflow/scripts/\w+\.py)"', rules))
        imported = set().union(*(library_imports(ROOT / s) for s in scripts))
        for module in (SRC / "studies" / room).glob("*.py"):
            assert str(module.relative_to(ROOT)) in imported, module


def test_rooms_import_each_other_without_a_circle():
    """The rooms of studies/ (and its shared modules) import each other one way only."""
    edges: dict[str, set[str]] = {}
    for path in (SRC / "studies").rglob("*.py"):
        parts = path.relative_to(SRC / "studies").parts
        room = parts[0] if len(parts) > 1 else parts[0].removesuffix(".py")
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("impactdamper.studies"):
                names = node.module.split(".")[2:3] or [a.name for a in node.names]
                edges.setdefault(room, set()).update(n for n in names if n != room)
    assert edges["claims"] >= {"replication"}  # the claims stage builds on the replication's claims

    def reaches(a: str, b: str, seen=()) -> bool:
        return any(n == b or (n not in seen and reaches(n, b, (*seen, n))) for n in edges.get(a, ()))

    assert not [room for room in edges if reaches(room, room)]


# How the source states the impact law (eqs. 14, 21-22) or carries its parameter R: the pulse
# D = m_red (1 + R), the rebound R v, the compiled kernels' slot, Siconos's impact law, and R
# handed to the Siconos driver.
IMPACT_LAW = [r"\b1(\.0)? \+ ([\w.\[\]]+\.)?R\b", r"\bR \* ", r"\bS_R\b", r"NewtonImpactNSL", r", 'R'\)"]


def _code(path: Path) -> str:
    """The module's code without its docstrings and comments."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr):
            if isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
                body[0] = ast.Pass()
    return ast.unparse(tree)


def test_impact_law_files_are_where_the_source_states_it():
    listed = DOC.split("<!-- impact-law files")[1].split("<!-- end of the impact-law files -->")[0]
    documented = set(re.findall(r"`((?:core|analysis|baselines|studies)/[\w/]+\.py)`", listed))
    found = {
        str(p.relative_to(SRC))
        for p in SRC.rglob("*.py")
        if any(re.search(pattern, _code(p)) for pattern in IMPACT_LAW)
    }
    assert documented == found, (
        "documented, not found:",
        documented - found,
        "found, not documented:",
        found - documented,
    )
    assert f"{len(found)} files that state the impact law" in DOC


def test_a_new_parameter_is_three_files_of_plumbing():
    """The files besides the parameter table that list every parameter by name are the config
    and its schema (ci.yaml, an overlay, has no reference section), and no Python file: 3 files
    of plumbing."""
    from impactdamper.core.parameters import PARAMETER_TABLE

    names = [s.name for s in PARAMETER_TABLE]
    listing = {
        str(p.relative_to(ROOT))
        for p in [*(ROOT / "config").glob("*.yaml"), *(ROOT / "workflow" / "schemas").glob("*.yaml")]
        if all(re.search(rf"^\s+{re.escape(n)}:", p.read_text(), flags=re.M) for n in names)
    }
    assert listing == {"config/config.yaml", "workflow/schemas/config.schema.yaml"}, listing
    assert "plumbing is 3 files" in " ".join(DOC.split())
    # ...and no Python file outside the table lists them all (the literal collections the
    # vocabulary scan finds; a continuation's domain, the CLI's flags, the kernels' columns and
    # the displays are read from the table).
    collections, _ = _vocabulary_scan()
    relative = {s.name for s in PARAMETER_TABLE if s.role != "scale"}
    assert not [h for h in collections if set(h[2].split(",")) >= relative], collections


# Where the project's own text (code, comments, docs, config, report sources) names a file of the
# library, a workflow script or a library module, the name must still point at something: a
# module moved into a room leaves no pointer to its old home behind.
TEXT_FOLDERS = ("src", "workflow", "docs", "config", "notebooks", "tools", "profiles", "paper/sections")
TEXT_SUFFIXES = {".py", ".md", ".yaml", ".smk", ".tex", ".sh", ".cff", ""}


@functools.cache
def _project_text() -> dict[str, str]:
    files = [ROOT / "README.md", ROOT / "Snakefile", ROOT / "paper" / "report.tex"]
    for folder in TEXT_FOLDERS:
        files += [p for p in (ROOT / folder).rglob("*") if p.is_file() and p.suffix in TEXT_SUFFIXES]
    return {str(p.relative_to(ROOT)): p.read_text(errors="replace") for p in files if "__pycache__" not in p.parts}


def test_tests_do_not_edit_the_import_path():
    """Tests import the package as installed (and tests/helpers.py through pytest's pythonpath);
    a script outside the package is loaded by its path, never by editing sys.path."""
    edits = [str(p.relative_to(ROOT)) for p in (ROOT / "tests").rglob("*.py") if "sys.path.insert" in p.read_text()]
    assert edits == [str(Path(__file__).relative_to(ROOT))]  # (this test's own text)


def test_paths_the_project_names_exist():
    missing = []
    for name, text in _project_text().items():
        for path in re.findall(
            r"\b(?:src/)?impactdamper/[\w/]+\.py|\bworkflow/(?:scripts|rules)/\w+\.(?:py|smk)", text
        ):
            full = path if path.startswith(("src/", "workflow/")) else f"src/{path}"
            if not (ROOT / full).exists():
                missing.append((name, path))
    assert not missing, missing


def test_dotted_names_the_project_names_resolve():
    import importlib

    def resolves(dotted: str) -> bool:
        parts = dotted.split(".")
        for i in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:i]))
            except ImportError:
                continue
            for attribute in parts[i:]:
                if not hasattr(obj, attribute):
                    return False
                obj = getattr(obj, attribute)
            return True
        return False

    # (a path such as envs/impactdamper.yaml is not a dotted name)
    names = {
        (f, n) for f, text in _project_text().items() for n in re.findall(r"(?<![/\w])impactdamper(?:\.\w+)+", text)
    }
    unresolved = sorted((f, n) for f, n in names if not resolves(n.removesuffix(".py")))
    assert not unresolved, unresolved


# The sizes the page states: a thin script, a module that owns one idea.
SCRIPT_LINES, MODULE_LINES, FUNCTION_LINES, INTERNAL_PUBLIC = 150, 600, 80, 30


def test_scripts_are_thin_and_modules_small():
    assert f"at most {SCRIPT_LINES} lines" in DOC and f"library module at most {MODULE_LINES}" in DOC
    scripts = {p.name: len(p.read_text().splitlines()) for p in (ROOT / "workflow" / "scripts").glob("*.py")}
    modules = {str(p.relative_to(SRC)): len(p.read_text().splitlines()) for p in SRC.rglob("*.py")}
    assert len(scripts) > 50 and len(modules) > 100  # (the globs found the trees)
    assert {n: k for n, k in scripts.items() if k > SCRIPT_LINES} == {}
    assert {n: k for n, k in modules.items() if k > MODULE_LINES} == {}


def _top_level_and_nested_functions(tree):
    """(qualified name, physical lines from the def to its last line) of every function."""
    out = []

    def visit(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                name = prefix + child.name
                if not isinstance(child, ast.ClassDef):
                    out.append((name, child.end_lineno - child.lineno + 1))
                visit(child, name + ".")

    visit(tree, "")
    return out


def test_functions_are_at_most_eighty_lines():
    """A function holds one step (its docstring included): the long ones are split along their
    steps, not trimmed to the line."""
    assert f"function at most {FUNCTION_LINES}" in DOC
    sizes = {
        f"{p.relative_to(SRC)}:{name}": lines
        for p in SRC.rglob("*.py")
        for name, lines in _top_level_and_nested_functions(ast.parse(p.read_text()))
    }
    assert len(sizes) > 1000 and max(sizes.values()) > 40  # (the walk found the functions)
    assert {n: k for n, k in sizes.items() if k > FUNCTION_LINES} == {}


def _references(path: Path) -> set:
    """Every name a module uses: a Name, an Attribute or an imported alias (not a string)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Name):
            found.add(node.id)
        elif isinstance(node, ast.Attribute):
            found.add(node.attr)
        elif isinstance(node, ast.alias):
            found.add(node.name.split(".")[-1])
    return found


def test_a_public_name_is_used_beyond_its_module():
    """A top-level function or class without a leading underscore is used by another module of
    the package, a workflow script or rule, a notebook or a tool; at most INTERNAL_PUBLIC are not
    (the library's types a reader meets through their dotted path in the project's text)."""
    modules = [p for p in SRC.rglob("*.py") if "__pycache__" not in p.parts]
    used = {p: _references(p) for p in modules}
    outside = set()
    for folder in ("workflow", "notebooks", "tools"):
        for p in (ROOT / folder).rglob("*.py"):
            outside |= _references(p)
    for p in (ROOT / "workflow" / "rules").glob("*.smk"):
        outside |= set(re.findall(r"[A-Za-z_]\w*", re.sub(r"#.*", "", p.read_text())))
    internal = []
    for p in modules:
        for node in ast.parse(p.read_text()).body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)) and not node.name.startswith("_"):
                if node.name not in outside and not any(node.name in used[q] for q in modules if q != p):
                    internal.append(f"{p.relative_to(SRC)}:{node.name}")
    assert len(modules) > 100 and len(internal) >= 1  # (the scan reads the package)
    assert len(internal) <= INTERNAL_PUBLIC, internal


# --- one vocabulary: the parameter table (core/parameters.py) is the only place that spells the
# parameters' names as a collection or their TeX symbols ------------------------------------------
VOCABULARY_FOLDERS = ("src", "workflow", "notebooks")
# (Every file spells the vocabulary through the table: issue 50 moved the last of them, the design
# variables, the compiled kernels' column lookups and the figures' and tables' symbols.)
# Hand-typed TeX symbols of the relative parameters (the table's ``symbol`` column); ``$\mu$s``
# is the microsecond.
HAND_SYMBOL = re.compile(r"\\delta_[12]|\\Delta_0/x|\\theta\b|\\mu\b(?!\$s)")


def _strings_and_collections(path: Path):
    """The module's string constants outside docstrings (f-strings' literal parts included), and
    its literal tuples, lists, sets, dict displays and dict(...) calls naming 3 or more
    parameters (at least half their string items): (line, names)."""
    from impactdamper.core.parameters import PARAMETER_TABLE

    names = {s.name for s in PARAMETER_TABLE}
    tree = ast.parse(path.read_text())
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(getattr(node, "body", None), list)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    strings, collections = [], []
    for node in ast.walk(tree):
        keys = None
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            strings.append((node.lineno, node.value))
        if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
            keys = [e.value for e in node.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)]
        elif isinstance(node, ast.Dict):
            keys = [k.value for k in node.keys if isinstance(k, ast.Constant) and isinstance(k.value, str)]
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "dict":
            keys = [k.arg for k in node.keywords if k.arg]
        named = [k for k in keys or () if k in names]
        if len(named) >= 3 and len(named) >= 0.5 * len(keys):
            collections.append((node.lineno, tuple(named)))
    return strings, collections


def _vocabulary_scan() -> tuple[list, list]:
    """(hand-typed collections of parameter names, hand-typed parameter symbols) over the
    project's Python outside the parameter table: (file, line, what) each."""
    collections, symbols = [], []
    for folder in VOCABULARY_FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.py")):
            name = str(path.relative_to(ROOT))
            if name == "src/impactdamper/core/parameters.py" or "__pycache__" in path.parts:
                continue
            strings, found = _strings_and_collections(path)
            collections += [(name, line, ",".join(k)) for line, k in found]
            symbols += [(name, line, text) for line, text in strings if HAND_SYMBOL.search(text)]
    return collections, symbols


def test_the_vocabulary_is_spelled_only_in_the_parameter_table():
    """Outside the table: at most 2 hand-typed collections of 3 or more parameter names (the
    readings' table columns, in their table's order; a hard case's data) and no hand-typed TeX
    symbol of a parameter anywhere."""
    collections, symbols = _vocabulary_scan()
    strings, found = _strings_and_collections(SRC / "core" / "parameters.py")
    assert found and any(HAND_SYMBOL.search(text) for _, text in strings)  # (the scan finds the table's own)
    assert len(collections) <= 2, collections
    assert symbols == [], symbols
