"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the linear references a
suppressor is judged against, each computed (none typed in).

Outputs ``figures/design_baselines.csv`` (per theta over the band: the bare object, the
absorber without a stop of the same mu, N, delta2, and the optimal TMDs) and
``figures/design_baselines.json`` (the TMDs optimised for the band's peak and for its average,
each reference's peak and band average, and the design search's check against Den Hartog's
closed form on an undamped object: the measured differences in N, delta2 and the peak).
"""

import logging

import numpy as np

from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper.studies.design.design import (
    band_mean,
    band_peak,
    bare_object_amplitude,
    den_hartog,
    design_band,
    design_parameters,
    optimal_tmd,
    two_mass_amplitude,
)
from impactdamper.studies.design.devices import TmdCriterion, Uncertainty
from impactdamper.studies.design.optimum import BUDGET, design_bounds
from impactdamper.studies.design.search import search


COLUMNS = ["theta", "bare", "absorber", "tmd_peak", "tmd_band_average"]


def den_hartog_check(mu: float, band: tuple) -> dict:
    """The design table's search (the same budget) on an undamped object against Den Hartog's
    closed form: the optimum's N, delta2 and peak, and their relative differences."""
    dh = den_hartog(mu)
    r = search(TmdCriterion(mu, 0.0, band, "peak", Uncertainty()), design_bounds(mu, 1.0)["tmd"], budget=BUDGET)
    return {
        "closed_form": dh,
        "search": r.to_dict(),
        "peak_relative_difference": r.value / dh["peak"] - 1.0,
        "N_relative_difference": r.x["N"] / dh["N"] - 1.0,
        "delta2_relative_difference": r.x["delta2"] / dh["delta2"] - 1.0,
    }


def main(reference: dict, design: dict, out_csv, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_baselines")
    p = design_parameters(reference, design)
    band = design_band(design)
    th = np.linspace(band[0], band[1], int(design["baseline_points"]))
    tmd = {c: optimal_tmd(p.mu, p.delta1, band, c) for c in ("peak", "band_average")}
    for c, t in tmd.items():
        log.info(
            "optimal TMD (%s): N = %.6f, delta2 = %.6f, peak %.6f, band average %.6f",
            c,
            t.N,
            t.delta2,
            t.peak,
            t.band_average,
        )
    check = den_hartog_check(p.mu, band)
    curves = {
        "bare": bare_object_amplitude(p.delta1, th),
        "absorber": two_mass_amplitude(p.mu, p.N, p.delta1, p.delta2, th),
        "tmd_peak": tmd["peak"].amplitude(th),
        "tmd_band_average": tmd["band_average"].amplitude(th),
    }
    write_csv(
        out_csv, COLUMNS, [{"theta": float(t), **{k: float(v[i]) for k, v in curves.items()}} for i, t in enumerate(th)]
    )
    refs = {
        "bare": lambda t: bare_object_amplitude(p.delta1, t),
        "absorber": lambda t: two_mass_amplitude(p.mu, p.N, p.delta1, p.delta2, t),
    }
    summary = {
        "band": list(band),
        "parameters": p.to_dict(),
        "references": {k: {"peak": band_peak(f, band), "band_average": band_mean(f, band)} for k, f in refs.items()},
        "tmd": {c: t.to_dict() for c, t in tmd.items()},
        "den_hartog_check": check,
    }
    write_json(out_json, summary)
    log.info(
        "Den Hartog check: the search's peak %.6f against the fixed-point height %.6f (%.2e), N %.2e, delta2 %.2e",
        check["search"]["value"],
        check["closed_form"]["peak"],
        check["peak_relative_difference"],
        check["N_relative_difference"],
        check["delta2_relative_difference"],
    )


JOB = "params.reference params.design output.csv output.json log=log"
STAGE = {"logger": "design_baselines", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
