# A run's own output tree (config key output_root). The rules name their files by paths relative
# to the working directory: "." (the default) is the repository itself, whose figures/ and
# paper/ are the committed record. Any other root becomes the working directory (`workdir:` in
# the Snakefile), so that everything the run writes (figures/, paper/, results/, logs/,
# .snakemake/) lands under it; the sources the rules read are reached there through symbolic
# links to the repository, so that the same relative paths name them. Included before
# common.smk, whose part lists glob the library's source (src/) in the working directory.
from pathlib import Path

from snakemake.exceptions import WorkflowError

# The repository's source directories the rules read (scripts, library, notebooks).
ROOT_LINKED = ("src", "workflow", "notebooks")
# paper/ holds sources (linked one by one) beside the report's outputs, made in the root.
ROOT_PAPER_OUTPUTS = ("generated", "report.pdf", "build")


def output_root(config):
    """The run's output root (config ``output_root``, default "."), with the repository's
    sources linked into it when it is not ".". A root in the record (figures/, paper/) or in the
    sources stops the run with one line naming the key: only results/ (git-ignored) or a place
    outside the repository may hold another run's outputs."""
    root = config.get("output_root", ".")
    if not isinstance(root, str) or not root.strip():
        raise WorkflowError(
            f"Error validating config file: ['output_root']: {root!r} is not allowed: must be a directory"
        )
    repo = Path(workflow.basedir).resolve()
    path = Path(root).resolve()
    if path == Path.cwd().resolve():
        return root
    if (path == repo or repo in path.parents) and (repo / "results") not in [path, *path.parents][:-1]:
        raise WorkflowError(
            f"Error validating config file: ['output_root']: {root!r} is not allowed: must be '.', "
            "a directory under results/ or one outside the repository (never the record in "
            "figures/ or paper/)"
        )
    path.mkdir(parents=True, exist_ok=True)
    links = [(path / name, repo / name) for name in ROOT_LINKED]
    (path / "paper").mkdir(exist_ok=True)
    links += [
        (path / "paper" / source.name, source)
        for source in sorted((repo / "paper").iterdir())
        if source.name not in ROOT_PAPER_OUTPUTS
    ]
    for link, target in links:
        if link.is_symlink() and link.resolve() != target:
            link.unlink()  # a link left by a clone elsewhere
        if not link.is_symlink():
            link.symlink_to(target, target_is_directory=target.is_dir())
    return root
