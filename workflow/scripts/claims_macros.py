"""The numbers the report and the README quote about where the paper's Fig. 2 claims hold
beyond the gap (Timofeev et al. 2019, DOI 10.18698/0236-3941-2019-1-90-100): the nearest
reproducing set in all seven parameters and the round values (figures/claims_nearest.json),
the refinement of the one-parameter search (figures/claims_by_parameter_settings.json), the
four pair maps (their cells, and how their grids were computed: their settings' ``grid``), and
the located range's end checks counted by what they rest on
(figures/located_case.json).

Outputs: ``results/report/claims.json`` (the stage's record of its macros,
:class:`impactdamper.reporting.latex.MacroFile`) and ``paper/generated/claims_macros.tex``.
"""

from pathlib import Path

from impactdamper.reporting.latex import render_macros
from impactdamper.reporting.records import read_csv, read_json, run_stage, write_json
from impactdamper.studies.claims.record import macros


RECORD_WHAT = "where the claims hold beyond the gap: the nearest set, round values, refinement, pair maps, end checks"


def main(nearest_json, search_json, map_csvs: dict, located_json, out_record, out_tex, map_jsons=None) -> dict:
    record = macros(
        read_json(nearest_json),
        read_json(search_json),
        {k: read_csv(v) for k, v in map_csvs.items()},
        read_json(located_json),
        grids={k: read_json(v)["grid"] for k, v in (map_jsons or {}).items()},
    ).record(RECORD_WHAT)
    write_json(out_record, record, sort_keys=False)
    Path(out_tex).parent.mkdir(parents=True, exist_ok=True)
    Path(out_tex).write_text(render_macros(record))
    return record


JOB = (
    "input.nearest input.search",
    lambda j: dict(zip(["R_gap", *j.params.pair_maps], j.input.maps)),
    "input.located output.record output.tex",
)
# The maps' settings by name, in the order of their CSVs.
MAP_JSONS = lambda j: dict(zip(["R_gap", *j.params.pair_maps], j.input.map_settings))  # noqa: E731

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, map_jsons=MAP_JSONS)  # noqa: F821 (injected by Snakemake's script: directive)
