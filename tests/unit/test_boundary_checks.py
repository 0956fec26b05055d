"""Tests of :mod:`impactdamper.analysis.boundary_checks` and of the boundary rows of
:mod:`impactdamper.analysis.boundaries` on hand-made maps and curves with known answers."""

import numpy as np

from impactdamper.analysis import boundary_checks as bc
from impactdamper.analysis.boundaries import closed_form_rows
from impactdamper.analysis.transitions import no_contact_gap, stuck_liftoff_gap
from impactdamper.core.parameters import Parameters


def _map():
    gaps = np.linspace(-1.0, 1.0, 21)  # cells 0.1 wide
    slow = np.linspace(0.0, 1.0, 11)  # rows 0.1 apart
    labels = np.where(gaps[None, :] < 0.05, "1/1", "0/1").repeat(len(slow), axis=0)
    return slow, gaps, labels


def test_label_changes_on_a_curve_are_within_one_cell_and_a_far_curve_has_none():
    slow, gaps, labels = _map()
    on = np.array([[0.05, 0.0], [0.05, 1.0]])  # the boundary itself (between columns 10 and 11)
    near = np.array([[0.14, 0.0], [0.14, 1.0]])  # 0.9 cell away
    far = np.array([[-0.5, 0.0], [-0.5, 1.0]])
    r = bc.label_changes_near_curves(slow, gaps, labels, {"on": on, "far": far})
    assert r["changes"] == len(slow) and r["within_one_cell"] == len(slow) and r["share"] == 1.0
    assert r["curves_without_change"] == ["far"]
    assert bc.label_changes_near_curves(slow, gaps, labels, {"near": near})["share"] == 1.0
    # 1.6 cells away: no change within one cell.
    r = bc.label_changes_near_curves(slow, gaps, labels, {"off": near + [0.07, 0.0]})
    assert r["within_one_cell"] == 0 and r["curves_without_change"] == ["off"]


def test_np_changes_are_counted_apart():
    slow, gaps, labels = _map()
    labels[3, :] = "np"
    r = bc.label_changes_near_curves(slow, gaps, labels, {"on": np.array([[0.05, 0.0], [0.05, 1.0]])})
    assert r["changes_without_np"] < r["changes"]
    assert r["share_without_np"] == 1.0 and r["share"] < 1.0


def test_what_each_kind_says_changes():
    assert bc._as_kind_says("period_doubling", "1/1", "2/2")
    assert not bc._as_kind_says("period_doubling", "1/1", "2/1") and not bc._as_kind_says(
        "period_doubling", "1/1", "np"
    )
    assert bc._as_kind_says("grazing_velocity", "1/1", "0/1") and bc._as_kind_says("grazing_velocity", "3/2", "1/1")
    assert not bc._as_kind_says("grazing_velocity", "1/1", "2/1")
    assert bc._as_kind_says("grazing_touch", "1/1", "2/1") and bc._as_kind_says("grazing_touch", "1/1", "c/1")
    assert not bc._as_kind_says("grazing_touch", "3/2", "1/1")
    assert bc._as_kind_says("fold", "3/2", "np") and not bc._as_kind_says("neimark_sacker", "3/2", "3/2")


def test_closed_form_rows_are_the_closed_forms_with_an_end_reason():
    base = Parameters(theta=1.0, mu=0.08, N=0.5, delta1=0.05, delta2=0.05, R=0.7, gap=-5.8)
    rows = closed_form_rows(base, "theta", ((-40.0, 15.0), (0.5, 1.5)), 11)
    fc = [r for r in rows if r["kind"] == "first_contact"]
    lo = [r for r in rows if r["kind"] == "liftoff"]
    assert len(fc) == 11 and len(lo) == 11
    assert all(r["gap"] == no_contact_gap(base.replace(theta=r["theta"])) for r in fc)
    assert all(r["gap"] == stuck_liftoff_gap(base.replace(theta=r["theta"])) for r in lo)
    assert [r["end_reason"] for r in fc].count("map_edge") == 1 and fc[-1]["end_reason"] == "map_edge"
