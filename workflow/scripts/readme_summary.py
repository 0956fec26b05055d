"""Writes the README's block of results (figures/readme_summary.md) from the workflow's outputs:
a short table of the results of the replication of Timofeev et al. (2019), DOI
10.18698/0236-3941-2019-1-90-100, and its extension (claim or question, verdict or answer, the
evidence in numbers, and the report's section that gives the long account).

Every number the README states comes from here: the report stages' records
(results/report/{verdict,orbits,performance,sweeps,design,claims}.json, the same records their TeX macro
files are rendered from, :class:`impactdamper.reporting.latex.MacroFile`). Only results that a
rerun reproduces exactly are quoted: timings change from run to run and stay in the report and
the repository's benchmark page, so that a user's own run leaves the README's copy current. The
README carries a verbatim copy of this file between its ``BEGIN generated`` and ``END
generated`` markers; tests/workflow/test_readme.py checks that the copy is current and that the
table says what the committed records say.
"""

import sys
from pathlib import Path

from impactdamper.core.parameters import RELATIVE_PARAMETERS
from impactdamper.reporting.readme import read_records, results_table
from impactdamper.studies.vocabulary import UNICODE

# The report's sections that give the long account, by their titles (tests/workflow/test_readme.py
# holds them to the report's \section titles).
REPRODUCTION = "Reproduction of the paper's Fig. 2"
ORBITS = "Periodic orbits and their stability"
SWEEPS = "Gap sweeps and regime maps"
DESIGN = "Choosing a suppressor"
PERFORMANCE = "Speed against error, and hard cases"
# The relative parameters as the README writes them (the parameter table's plain names in Unicode).
SYMBOLS = {name: UNICODE[name] for name in RELATIVE_PARAMETERS}
GAP, THETA = SYMBOLS["gap"], SYMBOLS["theta"]


def rows(m: dict[str, str]) -> list[tuple[str, str, str, str]]:
    """The table's rows: (claim or question, verdict or answer, evidence, the report's section)."""
    stated = f"at the stated case ({GAP} = {m['StatedGap']})"
    ivp = (
        f"the independent solve_ivp integration settles to the same cycle: impact times differ by "
        f"{m['StatedIvpTimeDiff']} T, closing velocities by {m['StatedIvpVelocityDiff']} x_st ω "
        f"(tolerance {m['CrosscheckTimeTol']} each)"
    )
    nearest = SYMBOLS.get(m["ClaimsNearestParameterName"], m["ClaimsNearestParameterName"])
    end_note = "; the nearer end depends on the solver" if m["ClaimsNearestEndNote"] else ""
    checks = [m[f"Sweep{c}Outcome"] for c in ("LiftOff", "FirstContact", "AlgOneGrazing")]
    within = sum(c == "within the tolerance" for c in checks)
    design = m["DesignRecommendationPlain"].split(":")[0]
    return [
        (
            f"The paper's Fig. 2a {stated}: Algorithm No. 1's gap is negative on (t1, t2)",
            f"**{m['ClaimAVerdict']}**",
            f"the one-impact orbit is admissible (impact phase {m['StatedAlgOneImpactPhase']}) and its gap stays "
            f"positive; solve_ivp's re-integration agrees (periodicity residual {m['StatedIvpAlgOneResidual']})",
            REPRODUCTION,
        ),
        (
            f"The paper's Fig. 2b {stated}: T_c = 2T",
            f"**{m['ClaimBPeriodVerdict']}**",
            f"Algorithm No. 2 settles to T_c = {m['StatedAlgTwoPeriod']}; {ivp}",
            REPRODUCTION,
        ),
        (
            f"The paper's Fig. 2b {stated}: three impacts per cycle",
            f"**{m['ClaimBImpactsVerdict']}**",
            f"{m['StatedAlgTwoImpacts']} impact per cycle",
            REPRODUCTION,
        ),
        (
            "Where both claims hold, the other parameters as stated",
            f"{GAP} in [{m['BothRangeLo']}, {m['BothRangeHi']}]",
            f"the {m['OrbitLabelDouble']} cycle (three impacts in two periods) is stable on "
            f"({m['OrbitStableDoubleLow']}, {m['OrbitStableDoubleHigh']}); at the located case {GAP} = "
            f"{m['LocatedGap']} Algorithm No. 2 settles to T_c = {m['LocatedAlgTwoPeriod']} with "
            f"{m['LocatedAlgTwoImpacts']} impacts, and solve_ivp's cycle differs by {m['LocatedIvpTimeDiff']} T",
            f"{REPRODUCTION}; {ORBITS}",
        ),
        (
            f"The nearest change of one parameter alone, at {GAP} = {m['StatedGap']}",
            f"{nearest} in [{m['ClaimsNearestLo']}, {m['ClaimsNearestHi']}], {m['ClaimsNearestRelDistance']} to "
            f"{m['ClaimsNearestFarRelDistance']} % from {m['ClaimsNearestStated']}",
            f"each of the six other parameters searched alone, grids refined where the motion changes{end_note}",
            REPRODUCTION,
        ),
        (
            "The nearest set of all seven parameters",
            f"no parameter changed by more than {m['NearestMaxDistMaxPct']} %",
            f"{THETA} and N raised together ({THETA} = {m['NearestMaxTheta']}, N = {m['NearestMaxN']}), with a "
            f"{m['NearestMarginPct']} % margin; {m['NearestRays']} rays and a local refinement (a near set, not a "
            "proven nearest one); the pure-Python solver and solve_ivp confirm both claims",
            REPRODUCTION,
        ),
        (
            "Another reading of the paper's definitions",
            f"{m['ReadingsReproducing']} of {m['ReadingsCount']} reproduces both claims",
            f"R read as the loss 1 − R (R = {m['RAsLossR']}), against the paper's own impact coefficient",
            REPRODUCTION,
        ),
        (
            "Three transitions of the gap sweep against their closed forms",
            f"{within} of 3 within {m['SweepCheckTolerance']}",
            f"lift-off of the persistent contact: difference {m['SweepLiftOffDifference']}, {m['SweepLiftOffOutcome']}: "
            "the model's contact resolution, worked out in the report",
            SWEEPS,
        ),
        (
            f"Impact suppressor or tuned-mass damper, over {THETA} = {m['DesignBandStart']} to {m['DesignBandStop']}",
            design,
            f"located peaks: the TMD {m['DesignTmdOptLocPeak']}, the impact suppressor with its stop in reach "
            f"{m['DesignHitLocPeak']} (bare object {m['DesignBareDevLocPeak']}); strokes: the TMD "
            f"{m['DesignTmdOptStroke']}, the impact suppressor {m['DesignHitStroke']}",
            DESIGN,
        ),
        (
            f"Accuracy of the exact solver, against a {m['PerfDigits']}-digit recomputation",
            f"impact-time error {m['PerfFirstExactError']} T",
            f"on the first {m['PerfNImpacts']} impacts ({m['PerfSettledExactError']} on the settled cycle); "
            f"solve_ivp's best {m['PerfFirstBestIvpError']}; {m['PerfHardCasesPassed']} of "
            f"{m['PerfHardCasesTotal']} hard cases pass all checks",
            PERFORMANCE,
        ),
    ]


def summary(m: dict[str, str]) -> str:
    lines = [
        "<!-- Generated by workflow/scripts/readme_summary.py (rule readme_summary); do not edit by hand. -->",
        "",
        *results_table(rows(m)),
        "",
        f"{GAP} is the initial gap over the static deflection; x_st ω the unit of velocities. The report "
        "(`paper/report.pdf`) gives the long account of each row in the section named, and its timings.",
    ]
    return "\n".join(lines) + "\n"


def main(records: list[str], output: str) -> None:
    Path(output).write_text(summary(read_records(records)))


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(list(sm.input.records), sm.output[0])
    else:  # python readme_summary.py OUT RECORD...
        main(sys.argv[2:], sys.argv[1])
