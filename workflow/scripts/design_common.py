"""Shared helpers of the design stage ("Choosing a suppressor"): parameters, settings and
grids from the config, and the stage's logger.

Not a figure script. The stage's scripts import it (Snakemake puts ``workflow/scripts`` on
``sys.path`` for ``script:`` rules; the tests import the scripts by path). The paper is
Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100.
"""

import numpy as np

from impactdamper.analysis.settled import SweepSettings
from impactdamper.core.parameters import Parameters
from impactdamper.core.simulate import Tolerances
from impactdamper.reporting.records import stage_logger

PAPER = "Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100"


def parameters(reference: dict, design: dict) -> Parameters:
    """The reference case with the design section's own mass ratio, spring, dampers and R."""
    values = {name: float(reference[name]) for name in Parameters.names()}
    values.update({name: float(design[name]) for name in ("mu", "N", "delta1", "delta2", "R") if name in design})
    return Parameters(**values)


def settings(sweep: dict, solver: dict) -> SweepSettings:
    """How each point settles: the sweep stage's caps (config ``sweep``), the solver's tolerances."""
    return SweepSettings(settle_tol=float(sweep["settle_tol"]), max_periods=int(sweep["max_periods"]),
                         max_periods_after_nonperiodic=int(sweep["max_periods_after_nonperiodic"]),
                         max_period_multiple=int(sweep["max_period_multiple"]),
                         tolerances=Tolerances(gap_tol=float(solver["gap_tol"]),
                                               chatter_tol=float(solver["chatter_tol"])))


def band(design: dict) -> tuple:
    return float(design["theta_start"]), float(design["theta_stop"])


def gaps(design: dict, prefix: str = "gap") -> np.ndarray:
    """The design chart's gaps Delta0/x_st (``gap_points`` from ``gap_start`` to ``gap_stop``)."""
    return np.linspace(float(design["gap_start"]), float(design["gap_stop"]), int(design[f"{prefix}_points"]))


def logger(log_path, name: str):
    """The rule's log, with the library's progress lines (sweeps) routed there too."""
    return stage_logger(log_path, name, timestamps=True, library=True)


def save(plt, fig, out_pdf, out_png) -> None:
    """Save a figure of the stage as PDF (report) and PNG (README), deterministically, and close it."""
    from impactdamper.reporting.plotting import save_figure

    save_figure(fig, out_pdf, formats=("pdf",))
    save_figure(fig, out_png, formats=("png",))
    plt.close(fig)


def figure_rule(sm, main, *inputs: str) -> None:
    """Run a figure script's ``main`` under Snakemake's ``script:``: the named inputs, then the
    outputs pdf and png; warnings and errors go to the rule's log."""
    import sys

    sys.stderr = open(sm.log[0], "w")
    main(*[sm.input[name] for name in inputs], sm.output.pdf, sm.output.png)
