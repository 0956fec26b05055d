# A run's own output tree (config key output_root, checked with the config: "." or a relative
# path under results/). The rules name their files by paths relative to the working directory:
# "." (the default) is the repository itself, whose figures/ and paper/ are the committed record.
# Any other root becomes the working directory (`workdir:` in the Snakefile), so that everything
# the run writes (figures/, paper/, results/, logs/, .snakemake/) lands under it; the sources the
# rules read are reached there through symbolic links to the repository, so that the same
# relative paths name them. A dry run (-n) writes none of it: see planning_directory().
import atexit
import shutil
import sys
import tempfile
from pathlib import Path

# The repository's source directories the rules read (scripts, library, notebooks).
ROOT_LINKED = ("src", "workflow", "notebooks")
# paper/ holds sources (linked one by one) beside the report's outputs, made in the root.
ROOT_PAPER_OUTPUTS = ("generated", "report.pdf", "build")


def root_links(repo, root):
    """(link, target) of every link to the repository's sources that output root ``root`` needs."""
    links = [(root / name, repo / name) for name in ROOT_LINKED]
    return links + [
        (root / "paper" / source.name, source)
        for source in sorted((repo / "paper").iterdir())
        if source.name not in ROOT_PAPER_OUTPUTS
    ]


def make_links(links):
    for link, target in links:
        link.parent.mkdir(parents=True, exist_ok=True)
        if link.is_symlink() and link.resolve() != target:
            link.unlink()  # a link left by a clone elsewhere
        if not link.is_symlink():
            link.symlink_to(target, target_is_directory=target.is_dir())


def planning_directory(repo, root):
    """Where a dry run plans output root ``root``: a temporary directory outside the repository
    with the links to the sources and to whatever the root already holds (its outputs, and its
    record of the last run's parameters and code, .snakemake/metadata, so that the plan is the
    run's), removed when Snakemake exits. The root itself is not touched, nor made."""
    plan = Path(tempfile.mkdtemp(prefix="impactdamper-dry-run-"))
    atexit.register(shutil.rmtree, plan, ignore_errors=True)
    links = root_links(repo, plan)
    if root.is_dir():
        own = [p for p in root.iterdir() if p.name not in (*ROOT_LINKED, "paper", ".snakemake")]
        own += [root / "paper" / name for name in ROOT_PAPER_OUTPUTS if (root / "paper" / name).exists()]
        own += [root / ".snakemake" / "metadata"] if (root / ".snakemake" / "metadata").is_dir() else []
        links += [(plan / p.relative_to(root), p) for p in own]
    make_links(links)
    print(f"Dry run: {root} planned in {plan} (removed at exit); nothing is written under it.", file=sys.stderr)
    return str(plan)


def output_root(config):
    """The run's working directory: its output root (config ``output_root``, default "."), with
    the repository's sources linked into it when it is not "." (a dry run plans it elsewhere)."""
    root = config.get("output_root", ".")
    repo = Path(workflow.basedir).resolve()
    path = repo / root
    if path.resolve() == repo:
        return root
    if workflow.output_settings.dryrun:
        return planning_directory(repo, path)
    make_links(root_links(repo, path))
    return str(path)
