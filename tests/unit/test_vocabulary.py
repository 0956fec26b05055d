"""The parameters' vocabulary (symbols, macro names, plain names, labels) comes from the one
parameter table (impactdamper.core.parameters.PARAMETER_TABLE), and every per-parameter set the
studies use derives from it (impactdamper.studies.vocabulary)."""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from impactdamper import Parameters
from impactdamper.core.parameters import PARAMETER_TABLE, RELATIVE_PARAMETERS
from impactdamper.reporting.latex import macro
from impactdamper.studies.vocabulary import SPEC, tex

ROOT = Path(__file__).resolve().parents[2]


def test_display_fields_are_usable_and_distinct():
    """Each macro-name part makes a TeX macro name (letters only); no two parameters share a
    macro part, a plain name, a symbol or a label (a record would show two as one)."""
    for field in ("macro", "plain", "symbol", "label"):
        values = [getattr(s, field) for s in PARAMETER_TABLE]
        assert all(values) and len(set(values)) == len(values), field
    for s in PARAMETER_TABLE:
        macro("Stated" + s.macro, "1")  # raises for a name that is not letters only
        assert "$" not in s.symbol and s.symbol in s.label.replace("$", ""), s.name
    assert tex("delta1") == "$\\delta_1$" and SPEC["gap"].plain == "Delta0/x_st"


def test_searched_and_designed_sets_derive_from_the_table():
    from impactdamper.studies.claims.search import SEARCH_PARAMETERS
    from impactdamper.studies.claims.claims_evaluator import NEAREST_NAMES
    from impactdamper.studies.design.design import DESIGN_FIELDS

    assert NEAREST_NAMES == RELATIVE_PARAMETERS == ("theta", "mu", "N", "delta1", "delta2", "R", "gap")
    assert SEARCH_PARAMETERS == ("theta", "mu", "N", "delta1", "delta2", "R")
    assert DESIGN_FIELDS == ("mu", "N", "delta1", "delta2", "R")
    # The committed record was searched along the same parameters, in the same order.
    record = json.loads((ROOT / "figures" / "claims_by_parameter_settings.json").read_text())
    assert tuple(record["parameters"]) == SEARCH_PARAMETERS


def test_the_workflow_runs_one_claims_job_per_searched_parameter():

    text = (ROOT / "workflow" / "rules" / "claims.smk").read_text()
    assert "CLAIMS_PARAMETERS = list(SEARCH_PARAMETERS)" in text
    assert not re.search(r'\["theta", "mu"', text)  # no literal copy of the set


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("theta", 0.0),
        ("theta", 1e-9),
        ("mu", -1e-3),
        ("delta1", 0.0),
        ("delta2", -1e-12),
        ("R", 1.0),
        ("R", 1.0 + 1e-12),
    ],
)
def test_the_nearest_search_domain_is_the_parameters_own(name, value):
    """A point of the nearest-set search is valid exactly where Parameters accepts it (the
    domain comes from the table's ranges), at and just beyond each bound."""
    from impactdamper.studies.claims.claims_evaluator import NEAREST_NAMES, ClaimsEvaluator

    base = Parameters()
    x = np.array([[value if n == name else getattr(base, n) for n in NEAREST_NAMES]])
    try:
        base.replace(**{name: value})
        accepted = True
    except ValueError:
        accepted = False
    assert bool(ClaimsEvaluator(base, 1e-12, settings=None).valid(x)[0]) == accepted


def test_readme_names_the_parameters_the_record_searched():
    """The README's table names the nearest single change by the parameter's symbol: every
    parameter the verdict's record searched alone (its macros, the committed TeX file holding the
    same names as its record) has one."""
    from readme_summary import SYMBOLS

    from impactdamper.core.parameters import PARAMETER_TABLE

    tex_file = (ROOT / "paper" / "generated" / "verdict_macros.tex").read_text()
    names = set(re.findall(r"\\newcommand\{\\([A-Za-z]+)\}", tex_file))
    searched = [s.name for s in PARAMETER_TABLE if f"Claims{s.macro}NearestBoth" in names]
    assert searched == ["theta", "mu", "N", "delta1", "delta2", "R"]
    assert set(searched) <= set(SYMBOLS)


def test_the_unicode_names_are_the_plain_names_with_greek_letters():
    """The README's parameter names (vocabulary.UNICODE) are the table's plain names with each
    word naming a Greek letter written as the letter, and nothing else changed."""
    from impactdamper.studies.vocabulary import UNICODE

    assert [UNICODE[s.name] for s in PARAMETER_TABLE] == ["θ", "μ", "N", "δ1", "δ2", "R", "Δ0/x_st", "ω", "x_st", "m1"]
