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
_ENV_PREFIX = Path(sys.prefix)
os.environ["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
os.environ["JUPYTER_PATH"] = os.pathsep.join(
    p for p in [str(_ENV_PREFIX / "share" / "jupyter"), os.environ.get("JUPYTER_PATH", "")] if p
)

# The library's source: every rule that imports it lists these as inputs, so a change to the
# solver reruns what it affects (Snakemake does not follow Python imports by itself).
# The command line (cli.py, __main__.py) is left out: no rule runs it and the package does not
# import it.
LIBRARY = sorted(
    str(p) for p in Path("src/impactdamper").glob("*.py") if p.name not in ("cli.py", "__main__.py")
)
STYLE = ["src/impactdamper/plotting.py", "src/impactdamper/paper.mplstyle"]
ENV = "../../envs/impactdamper.yaml"

# Final products of each stage; rule all asks for all of them.
ALL_TARGETS = []


def parameters_json(section="reference"):
    """The reference parameters as JSON, for a rule's params (reruns when they change)."""
    return json.dumps(config[section], sort_keys=True)


# Sweeps stage (issue 5): the chunk files a gather rule waits for.
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


def yaml_scalars(node):
    """Snakemake hands the values of a nested --config dict over as strings; read them as YAML
    scalars, so that --config reference='{theta: 1.1, ...}' is typed like the config file."""
    if isinstance(node, dict):
        return {key: yaml_scalars(value) for key, value in node.items()}
    if isinstance(node, list):
        return [yaml_scalars(value) for value in node]
    return yaml.safe_load(node) if isinstance(node, str) else node
