"""The ``boundaries`` command: a small plane around the reference case, its JSON, bad input."""

import json

import pytest

from impactdamper.analysis.transitions import no_contact_gap
from impactdamper.cli import main
from impactdamper.core.parameters import Parameters


def test_boundaries_json_holds_the_curves_and_the_closed_forms(capsys):
    status = main(["boundaries", "--plane", "theta", "--min", "0.97", "--max", "1.03", "--seed-rows", "1", "--json"])
    assert status == 0
    r = json.loads(capsys.readouterr().out)
    assert r["plane"] == "theta" and r["parameter"] == "theta" and r["range"] == [0.97, 1.03]
    kinds = {c["kind"] for c in r["curves"]}
    assert {"period_doubling", "grazing_velocity", "grazing_touch"} <= kinds
    # The 1/1 zero-velocity grazing is the first contact U1/x_st of the closed form.
    g = next(c for c in r["curves"] if c["kind"] == "grazing_velocity" and c["cycle"] == "1/1")
    p = Parameters()
    assert max(abs(a - no_contact_gap(p.replace(theta=t))) for a, t in g["points"]) <= 1e-8
    assert all(len(c["ends"]) == 2 for c in r["curves"]) and r["closed_form"]["first_contact"]


@pytest.mark.parametrize(
    "argv, flag",
    [(["--seed-rows", "0"], "--seed-rows"), (["--min", "1.2", "--max", "1.1"], "--min"), (["--plane", "x"], "--plane")],
)
def test_bad_input_is_one_line_naming_the_flag(capsys, argv, flag):
    with pytest.raises(SystemExit) as e:
        main(["boundaries", *argv])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and flag in err
