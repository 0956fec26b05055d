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

from impactdamper.analysis.linear_device import LinearDevice, den_hartog
from impactdamper.reporting.records import run_stage, write_csv, write_json
from impactdamper.studies.design.design import LINEAR_GRID_POINTS, design_band, design_parameters
from impactdamper.studies.design.devices import TmdCriterion, Uncertainty
from impactdamper.studies.design.optimum import optimal_tmd
from impactdamper.studies.design.search_setup import BUDGET, design_bounds
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


def summary(device: LinearDevice, band: tuple) -> dict:
    """A linear device's peak over the band (exact) and its band average (LINEAR_GRID_POINTS)."""
    return {
        "peak": float(device.peak(band)[1]),
        "band_average": device.band_average(np.linspace(band[0], band[1], LINEAR_GRID_POINTS)),
    }


def optimal(mu: float, delta1: float, band: tuple, criterion: str) -> tuple[LinearDevice, dict]:
    """The optimal TMD for ``criterion`` (the design table's optimiser, nominal) and its record."""
    r = optimal_tmd(TmdCriterion(mu, delta1, band, criterion, Uncertainty()))
    device = LinearDevice(mu, r.x["N"], delta1, r.x["delta2"])
    record = {"mu": mu, "delta1": delta1, "band": list(band), "criterion": criterion, **r.x}
    return device, {**record, **summary(device, band), "evaluations": r.evaluations}


def main(reference: dict, design: dict, out_csv, out_json, log=None) -> None:
    log = log if log is not None else logging.getLogger("design_baselines")
    p = design_parameters(reference, design)
    band = design_band(design)
    th = np.linspace(band[0], band[1], int(design["baseline_points"]))
    devices = {"bare": LinearDevice.bare(p.delta1), "absorber": LinearDevice.of(p)}
    tmd = {}
    for c in ("peak", "band_average"):
        devices[f"tmd_{c}"], tmd[c] = optimal(p.mu, p.delta1, band, c)
        log.info(
            "optimal TMD (%s): N = %.6f, delta2 = %.6f, peak %.6f, band average %.6f",
            c,
            tmd[c]["N"],
            tmd[c]["delta2"],
            tmd[c]["peak"],
            tmd[c]["band_average"],
        )
    check = den_hartog_check(p.mu, band)
    curves = {k: d.amplitude(th) for k, d in devices.items()}
    write_csv(
        out_csv, COLUMNS, [{"theta": float(t), **{k: float(v[i]) for k, v in curves.items()}} for i, t in enumerate(th)]
    )
    record = {
        "band": list(band),
        "parameters": p.to_dict(),
        "references": {k: summary(devices[k], band) for k in ("bare", "absorber")},
        "tmd": tmd,
        "den_hartog_check": check,
    }
    write_json(out_json, record)
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
