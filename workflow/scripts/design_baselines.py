"""Extends Timofeev et al. (2019), DOI 10.18698/0236-3941-2019-1-90-100: the linear references a
suppressor is judged against, each computed (none typed in).

Outputs ``figures/design_baselines.csv`` (per theta over the band: the bare object, the
absorber without a stop of the same mu, N, delta2, and the optimal TMDs) and
``figures/design_baselines.json`` (the TMDs optimised for the band's peak and for its average,
Den Hartog's closed form and the optimiser's result for an undamped object as its check, and
each reference's peak and band average).
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


COLUMNS = ["theta", "bare", "absorber", "tmd_peak", "tmd_band_average"]


def main(reference: dict, design: dict, out_csv, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_baselines")
    p = design_parameters(reference, design)
    band = design_band(design)
    th = np.linspace(band[0], band[1], int(design["baseline_points"]))
    tmd = {c: optimal_tmd(p.mu, p.delta1, band, c) for c in ("peak", "band_average")}
    for c, t in tmd.items():
        log.info(
            "optimal TMD (%s): N = %.6f, delta2 = %.6f, peak %.6f, band average %.6f (%d evaluations)",
            c,
            t.N,
            t.delta2,
            t.peak,
            t.band_average,
            t.evaluations,
        )
    # The optimiser's check: an undamped object over a band wide enough to hold both peaks.
    check = optimal_tmd(p.mu, 0.0, band, "peak")
    dh = den_hartog(p.mu)
    dh_peak_at_dh = band_peak(lambda t: two_mass_amplitude(p.mu, dh["N"], 0.0, dh["delta2"], t), band)
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
        "den_hartog_check": {
            "closed_form": dh,
            "optimiser": check.to_dict(),
            "peak_at_closed_form": dh_peak_at_dh,
            "peak_relative_excess": check.peak / dh["peak"] - 1.0,
            "N_relative_difference": check.N / dh["N"] - 1.0,
            "delta2_relative_difference": check.delta2 / dh["delta2"] - 1.0,
        },
    }
    write_json(out_json, summary)
    log.info(
        "Den Hartog check: optimiser peak %.6f against the fixed-point height %.6f (excess %.2e), N %.6f against %.6f",
        check.peak,
        dh["peak"],
        check.peak / dh["peak"] - 1.0,
        check.N,
        dh["N"],
    )


JOB = "params.reference params.design output.csv output.json log=log"
STAGE = {"logger": "design_baselines", "timestamps": True, "library": True}

if __name__ == "__main__":
    run_stage(snakemake, main, JOB, **STAGE)  # noqa: F821 (injected by Snakemake's script: directive)
