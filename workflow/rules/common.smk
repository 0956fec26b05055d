# Shared helpers for every stage.
import json
import os
import sys
from pathlib import Path

# The solver's matrices are 4 x 4: BLAS threads never help them, and on a loaded machine
# OpenBLAS's thread hand-offs slow the matrix-exponential path by up to ~90x (see
# tests/conftest.py). Snakemake sets a job's BLAS threads to the job's threads, which a job
# spends on worker processes instead: every script's start (reporting/records.py's
# start_stage) sets one BLAS thread again (impactdamper.core.blas). This is the default for
# Snakemake itself and the notebooks' kernels.
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
# imports by itself). The command line (cli/, __main__.py) is no part: no rule runs it and
# the package does not import it.
def library_files(part):
    """The .py files of library part ``part``: a subpackage (``core``, with its own
    subpackages such as ``core/compiled``) or one module (``studies/claims/search``), paths
    relative to the repository (found there, whatever the working directory)."""
    repo = Path(workflow.basedir)
    path = repo / "src" / "impactdamper" / part
    if path.with_suffix(".py").is_file():
        return [str(path.with_suffix(".py").relative_to(repo))]
    return sorted(str(p.relative_to(repo)) for p in path.rglob("*.py"))


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


# The workflow's own cost: every job's Snakemake benchmark (wall time, CPU time of the job's
# processes), gathered by rule workflow_cost (report.smk) into the report's table of the costliest
# rules, with each Python job's exact CPU time (impactdamper.reporting.records.JOB_COST_DIR). One
# file per job, named as records.job_name names it: the rule's name, then its wildcards' values in
# the order of their names, each after a "-".
BENCHMARK_DIR = "results/benchmarks/rules"


def planned_cores():
    """The run's --cores (0 where none is given: a --dag, a --lint)."""
    from snakemake.exceptions import WorkflowError

    try:
        return int(workflow.cores)
    except (WorkflowError, TypeError):
        return 0


def benchmark_file(rule_name, *wildcards):
    """The benchmark file of a job of rule ``rule_name`` whose output has ``wildcards``."""
    return f"{BENCHMARK_DIR}/{rule_name}" + "".join(f"-{{{w}}}" for w in sorted(wildcards)) + ".tsv"


# A job's CPU time: Snakemake samples its processes (every 0.5 s in its first 15 s, then every
# 30 s) into the benchmark file; every Python job also writes its exact CPU time when it ends
# (reporting.records.start_stage), which the cost table prefers. Sampling more often cost the
# scheduler a sixth of a core.


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


def random_chunk_files(wildcards):
    """Chunk outputs of the random initial states (config sweep.random_chunks jobs)."""
    return expand("results/sweeps/random_{chunk}.csv", chunk=range(config["sweep"]["random_chunks"]))


# The config, checked before anything is planned or written (impactdamper.studies.config_check):
# a value the workflow cannot use stops the run, dry runs included, with one line naming the key.
def checked_config(config):
    """The config with its values typed as the schema expects (updated in place), or a
    WorkflowError of one line naming the key."""
    from snakemake.exceptions import WorkflowError

    from impactdamper.studies import config_check

    schema = config_check.read_schema(Path(workflow.basedir, "workflow", "schemas", "config.schema.yaml"))
    files = list(workflow.configfiles) + list(workflow.overwrite_configfiles or [])
    try:
        config.update(config_check.check(config, schema, files=dict.fromkeys(str(f) for f in files)))
    except config_check.ConfigError as err:
        raise WorkflowError(str(err)) from None  # (raised here: Snakemake lists the frames under it)
    return config


# Report stage: the report's appendix of provenance (rule provenance) reads the workflow's own
# rules and the project's citation metadata, when its job is planned (after every rules file is
# parsed).
def workflow_rules(wildcards):
    """The workflow's rules as JSON, for the report's appendix of provenance (name, script
    relative to the repository, output patterns, input patterns other than sources)."""
    repo = Path(workflow.basedir)
    rules = []
    for r in workflow.rules:
        script = None
        if r.script:
            script = os.path.relpath(os.path.normpath(Path(r.snakefile).parent / r.script), repo)
        # (an input named `stages` only orders a job after all the others, and is not read)
        order_only = set()
        if "stages" in r.input._names:
            start, end = r.input._names["stages"]
            order_only = set(range(start, start + 1 if end is None else end))
        inputs = [
            str(i)
            for k, i in enumerate(r.input)
            if k not in order_only and isinstance(i, str) and not str(i).startswith(("src/", "workflow/"))
        ]
        rules.append({"name": r.name, "script": script, "outputs": [str(o) for o in r.output], "inputs": inputs})
    return json.dumps({"rules": rules})


def citation_metadata(wildcards):
    """The project's citation metadata (CITATION.cff) as JSON, for the report's author line and locator."""
    import yaml

    return json.dumps(yaml.safe_load((Path(workflow.basedir) / "CITATION.cff").read_text()), sort_keys=True)
