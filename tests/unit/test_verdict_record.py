"""Tests of the verdict's macros (:mod:`impactdamper.studies.replication.record`) on the committed
record: the period and the velocity and impulse units come from :class:`Parameters` (change
the forcing frequency and they follow), and every claim has its verdict."""

import copy
import json
import math
from pathlib import Path

import pytest

from impactdamper import Parameters
from impactdamper.studies.replication.record import claims_macros, macros

FIG = Path(__file__).resolve().parents[2] / "figures"


def _load(name):
    return json.loads((FIG / name).read_text())


@pytest.fixture(scope="module")
def inputs():
    ref_s, ref_l = _load("reference_stated.json"), _load("reference_located.json")
    cc_s, cc_l = _load("crosscheck_stated.json"), _load("crosscheck_located.json")
    scan, rd = _load("located_case.json"), _load("other_readings.json")
    rows = _load("verdict.json")["claims"]
    return ref_s, ref_l, cc_s, cc_l, scan, rd, rows


def _values(mf):
    return {e["name"]: e["tex"] for e in mf.entries if "name" in e}


def test_period_and_units_follow_the_parameters(inputs):
    ref_s = inputs[0]
    m = _values(macros(*inputs))
    assert float(m["StatedT"]) == pytest.approx(Parameters(**ref_s["parameters"]).T, abs=5e-5)
    row = ref_s["algorithm2"]["impact_table"][0]
    p = Parameters(**ref_s["parameters"])
    assert float(m["StatedImpactOneVelocity"]) == pytest.approx(row["velocity"] / (p.x_st * p.omega), abs=5e-4)
    # Twice the forcing frequency: half the period; velocities in units of x_st omega halve.
    fast = copy.deepcopy(ref_s)
    fast["parameters"]["omega"] *= 2
    m2 = _values(macros(fast, *inputs[1:]))
    assert float(m2["StatedT"]) == pytest.approx(math.pi / p.omega, abs=5e-5)
    assert float(m2["StatedImpactOneVelocity"]) == pytest.approx(0.5 * float(m["StatedImpactOneVelocity"]), abs=1e-3)


def test_every_claim_has_a_verdict_and_the_claims_search_its_macros(inputs):
    m = _values(macros(*inputs))
    for name in ("ClaimA", "ClaimBPeriod", "ClaimBImpacts"):
        assert m[name + "Verdict"] in ("reproduced", "not reproduced")
    beyond = _load("verdict.json")["beyond_the_gap"]
    c = _values(claims_macros(beyond))
    assert all(name.isalpha() for name in c)
    assert c["ClaimsMapCells"] == str(beyond["map_cells"])
