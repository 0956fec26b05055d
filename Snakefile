# Replication and extension of Timofeev, Lyuminarskiy & Lyuminarskiy (2019),
# DOI 10.18698/0236-3941-2019-1-90-100. Thin entry point: config, validation, one rules file
# per stage; each stage adds its final products to ALL_TARGETS.
from snakemake.utils import min_version, validate

min_version("8.0")


configfile: "config/config.yaml"  # a --configfile (config/ci.yaml) is merged over it, key by key


include: "workflow/rules/common.smk"


# The config checked first (one line naming a bad key), then the schema's defaults filled in.
validate(checked_config(config), "workflow/schemas/config.schema.yaml")


include: "workflow/rules/output_root.smk"


# Everything the run writes goes under its output root ("." = the repository and its record).
workdir: output_root(config)


include: "workflow/rules/reference.smk"
include: "workflow/rules/claims.smk"
include: "workflow/rules/sweeps.smk"
include: "workflow/rules/notebooks.smk"
include: "workflow/rules/performance.smk"
include: "workflow/rules/orbits.smk"
include: "workflow/rules/design.smk"
include: "workflow/rules/lyapunov.smk"
include: "workflow/rules/reproducibility.smk"
include: "workflow/rules/report.smk"  # last: the report takes every stage's products


rule all:
    default_target: True
    input:
        ALL_TARGETS,
