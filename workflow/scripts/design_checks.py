"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the located worst branch
checked three independent ways (impactdamper.studies.design.checks): slow sweeps ten times
finer in both directions, the closed form of the motion without contact at its first contact,
and solve_ivp on the located peak's motion. Cases: the paper's suppressor at Delta0/x_st = 2
(the response command's example), a suppressor whose worst branch ends where the motion without
contact first touches its stop (a jump no sweep sample brackets), and the design table's impact
suppressors optimal for the peak and for the detuned worst case.

Outputs ``figures/design_checks.json``.
"""

import logging

from impactdamper.core.parameters import Parameters
from impactdamper.reporting.records import Timer, read_json, run_stage, write_json
from impactdamper.studies.design.checks import located_peak_checks
from impactdamper.studies.design.design import design_band, design_parameters
from impactdamper.studies.design.devices import DESIGN_SETTINGS, IMPACT_NAMES, impact_parameters
from impactdamper.studies.design.verdict import device

# A suppressor on the reference object whose worst branch is the motion without contact up to
# its first contact (found by the design search of an earlier version; the sweeps' samples jump
# past it).
BRANCH_END = dict(zip(IMPACT_NAMES, (5.332, 0.597, 0.061, 0.405)))


def main(reference: dict, design: dict, optimum_json, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_checks")
    p = design_parameters(reference, design)
    opt = read_json(optimum_json)
    cases = [
        ("gap_two", p.replace(gap=2.0)),
        ("branch_end", Parameters(**{**p.to_dict(), **BRANCH_END})),
        ("optimal_peak", impact_parameters(p.mu, p.delta1, device(opt, "impact_peak_reach")["parameters"])),
        ("robust_detuning", impact_parameters(p.mu, p.delta1, device(opt, "impact_detuning")["parameters"])),
    ]
    with Timer() as t:
        record = located_peak_checks(cases, design_band(design), DESIGN_SETTINGS)
    record.update({name: record["cases"][name] for name, _ in cases})
    write_json(out_json, record)
    log.info(
        "slow sweeps at most %.2e above the located peaks and %.2e below; floor %.2e; solve_ivp %.2e (%d); %.1f s",
        record["fine_largest_excess"],
        record["fine_largest_shortfall"],
        record["floor_largest_difference"],
        record["ivp_largest_difference"],
        record["ivp_count"],
        t.wall,
    )


JOB = "params.reference params.design input.optimum output.json log=log"
STAGE = {"logger": "design_checks", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
