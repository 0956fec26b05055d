"""Tests of the branch readings of :mod:`impactdamper.studies.sweeps.branches`: the special points'
vocabulary, a branch split into runs of one state for drawing, the multi-impact window and
the special points' descriptions. Hand-made rows (strings, as the committed CSVs are read)."""

import pytest

from impactdamper.analysis.branch import SPECIAL_KINDS
from impactdamper.studies.sweeps import branches as br


def test_vocabulary_names_every_kind_the_continuation_reports():
    assert set(br.SPECIAL_POINT_NAMES) == set(SPECIAL_KINDS)
    for table in (br.KIND_SHORT, br.KIND_TEXT, br.KIND_MARK, br.KIND_MACRO, br.KIND_LEGEND):
        assert set(table) == set(SPECIAL_KINDS)
    # TeX macro names are letters only, and tell every kind apart.
    assert all(m.isalpha() for m in br.KIND_MACRO.values())
    assert len(set(br.KIND_MACRO.values())) == len(SPECIAL_KINDS)
    assert len(set(br.KIND_LEGEND.values())) == len(SPECIAL_KINDS)


def _row(i, gap, y, stable="1", admissible="1"):
    return {
        "branch": "b",
        "index": str(i),
        "gap": f"{gap:g}",
        "x1_max": f"{y:g}",
        "stable": stable,
        "admissible": admissible,
    }


def test_run_pieces_split_at_state_changes_through_special_points():
    rows = [_row(0, 0.0, 1.0), _row(1, 1.0, 2.0), _row(2, 2.0, 3.0, stable="0"), _row(3, 3.0, 4.0, admissible="0")]
    # A period doubling between rows 1 and 2 (index 2: before row 2).
    special = [{"index": "2", "gap": "1.5", "x1_max": "2.5"}]
    pieces = br.run_pieces(rows, special, "x1_max")
    states = [s for s, _, _ in pieces]
    # The segment from row 2 to row 3 takes the state of its first regular end (unstable).
    assert states == ["stable", "unstable"]
    assert list(pieces[0][1]) == [0.0, 1.0, 1.5]  # ends at the special point
    assert list(pieces[1][1]) == [1.5, 2.0, 3.0] and list(pieces[1][2]) == [2.5, 3.0, 4.0]
    rows.append(_row(4, 4.0, 5.0, admissible="0"))
    assert [s for s, _, _ in br.run_pieces(rows, special, "x1_max")] == ["stable", "unstable", "inadmissible"]
    seq = br._branch_sequence(rows, special, "x1_max")
    assert [g for g, _, _ in seq] == [0.0, 1.0, 1.5, 2.0, 3.0, 4.0] and seq[2][2] is None


def test_run_pieces_skip_points_without_a_value():
    rows = [_row(0, 0.0, 1.0), _row(1, 1.0, 2.0)]
    special = [{"index": "1", "gap": "0.5", "x1_max": "nan"}]
    assert br.run_pieces(rows, special, "x1_max") == []


def test_multi_impact_window():
    rows = [{"branch": "single", "gap": "-20"}, {"branch": "double", "gap": "-6"}, {"branch": "double", "gap": "-5"}]
    special = [{"branch": "double", "gap": "-6.5"}, {"branch": "single", "gap": "-30"}]
    summary = {"branches": {"single": {"k": 1, "z": 1}, "double": {"k": 2, "z": 3}}}
    assert br.multi_impact_window(rows, special, summary, 0.25) == (-6.75, -4.75)


def test_describe_special_reads_stability_from_the_neighbouring_rows():
    rows = [_row(0, -7.0, 1.0, stable="1"), _row(1, -6.0, 1.0, stable="0")]
    pd = {
        "kind": "period_doubling",
        "label": "1/1",
        "index": "1",
        "gap": "-6.5",
        "detail": "a multiplier passes through -1: a 2/2 (doubled) cycle branches off",
    }
    assert br.describe_special(pd, rows) == "multiplier $-1$, a 2/2 cycle branches off; stable for smaller gaps"
    fold = dict(pd, kind="fold", detail="")
    assert br.describe_special(fold, rows).endswith("a stable and an unstable leg meet")
    graze = {"kind": "grazing_interior", "label": "3/2", "index": "1", "gap": "-6.5", "detail": "... -> 4/2 ..."}
    assert br.describe_special(graze, rows) == "the gap touches zero between impacts: a new impact (3/2 $\\to$ 4/2)"


@pytest.mark.parametrize("kind", sorted(SPECIAL_KINDS))
def test_every_kind_is_described(kind):
    rows = [_row(0, 0.0, 1.0), _row(1, 1.0, 1.0)]
    assert br.describe_special({"kind": kind, "label": "1/1", "index": "1", "gap": "0.5", "detail": ""}, rows)
