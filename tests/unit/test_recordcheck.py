"""The reproduction check (reporting/recordcheck.py): it passes on the committed record copied
as it is, and fails on a record with one settled number moved by 1e-6 or one label changed away
from any sensitive point; a label changed at a sensitive point passes and is counted."""

import csv
import io
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from impactdamper.reporting.record_tolerances import DEFAULT, TOLERANCES, tolerance_of
from impactdamper.reporting.recordcheck import check_record, _compare_file, _compare_text

ROOT = Path(__file__).resolve().parents[2]
SWEEP = "figures/sweep_gap.csv"
MAP = "figures/map_theta.csv"


def _copy(tmp_path, *paths):
    """A record of ``paths`` (and nothing else) copied from the committed one."""
    for name in ("reference", "new"):
        for path in paths:
            (tmp_path / name / path).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(ROOT / path, tmp_path / name / path)
    return tmp_path / "new", str(tmp_path / "reference")


def _rows(path):
    return list(csv.reader(io.StringIO(path.read_text())))


def _write(path, rows):
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows(rows)
    path.write_text(out.getvalue())


def _settled_row(rows):
    """A settled chatter point in the middle of a run of ten equal labels (no label change near)."""
    header = rows[0]
    label = header.index("label")
    for i in range(10, len(rows) - 10):
        if rows[i][label] == "c/1" and all(rows[j][label] == "c/1" for j in range(i - 5, i + 6)):
            return i
    raise AssertionError("no settled run in the sweep")


def test_the_committed_record_passes_against_itself(tmp_path):
    new, reference = _copy(tmp_path, SWEEP, MAP, "paper/generated/sweep_macros.tex", "figures/sweep_checks.json")
    verdicts = check_record(new, reference, ROOT)
    assert [v.status for v in verdicts] == ["pass"] * 4
    assert all(v.detail == "identical" for v in verdicts)


def _sweep_edited(tmp_path, column, edit):
    """The sweep's record with one settled point's ``column`` edited, checked against the committed one."""
    new, reference = _copy(tmp_path, SWEEP)
    rows = _rows(new / SWEEP)
    i, j = _settled_row(rows), rows[0].index(column)
    rows[i][j] = edit(rows[i][j])
    _write(new / SWEEP, rows)
    (verdict,) = check_record(new, reference, ROOT)
    return verdict


def test_a_settled_number_moved_by_1e_6_fails(tmp_path):
    verdict = _sweep_edited(tmp_path, "x1_max", lambda x: repr(float(x) + 1e-6))
    assert verdict.status == "fail" and "x1_max" in verdict.detail, verdict.line()


def test_a_number_moved_at_round_off_passes(tmp_path):
    verdict = _sweep_edited(tmp_path, "x1_max", lambda x: repr(float(x) * (1 + 1e-13)))
    assert verdict.status == "pass" and verdict.numbers == 1, verdict.line()


def test_a_label_changed_away_from_any_sensitive_point_fails(tmp_path):
    verdict = _sweep_edited(tmp_path, "label", lambda x: "1/1")
    assert verdict.status == "fail" and "no sensitive point" in verdict.detail, verdict.line()


def test_a_label_changed_next_to_a_label_change_passes_and_is_counted(tmp_path):
    new, reference = _copy(tmp_path, SWEEP)
    rows = _rows(new / SWEEP)
    label = rows[0].index("label")
    i = next(
        j
        for j in range(2, len(rows) - 1)
        if rows[j][label] != rows[j + 1][label]
        and rows[j][0] == rows[j + 1][0]
        and "np" not in (rows[j][label], rows[j + 1][label])
    )
    rows[i][label] = rows[i + 1][label]  # the boundary moved by one point
    _write(new / SWEEP, rows)
    (verdict,) = check_record(new, reference, ROOT)
    assert verdict.status == "pass" and verdict.sensitive == 1 and verdict.allowed >= 1, verdict.line()


def test_a_map_cell_flipped_inside_a_region_fails_and_at_its_edge_passes(tmp_path):
    new, reference = _copy(tmp_path, MAP)
    rows = _rows(new / MAP)
    cells = [r[1:] for r in rows[1:] if r[0] != "slow"]

    def uniform(i, j, k=3):
        return all(cells[a][b] == cells[i][j] for a in range(i - k, i + k + 1) for b in range(j - k, j + k + 1))

    inside = next(
        (i, j)
        for i in range(3, len(cells) - 3)
        for j in range(3, len(cells[0]) - 3)
        if uniform(i, j) and cells[i][j] != "np"
    )
    rows[inside[0] + 1][inside[1] + 1] = "9/9"
    _write(new / MAP, rows)
    (verdict,) = check_record(new, reference, ROOT)
    assert verdict.status == "fail", verdict.line()


def test_too_many_sensitive_differences_fail(tmp_path):
    new, reference = _copy(tmp_path, MAP)
    rows = _rows(new / MAP)
    flipped = 0
    for r in rows[1:]:
        for j in range(1, len(r)):
            if r[j] == "np":
                r[j], flipped = "1/1", flipped + 1
    _write(new / MAP, rows)
    (verdict,) = check_record(new, reference, ROOT)
    assert flipped > verdict.allowed and verdict.status == "fail", (flipped, verdict.line())


def test_printed_numbers_within_their_last_digit():
    tol = tolerance_of("paper/generated/design_macros.tex")
    a = "\\newcommand{\\X}{0.0925}\n"
    assert _compare_text(a, "\\newcommand{\\X}{0.0926}\n", tol).problems == []
    assert _compare_text(a, "\\newcommand{\\X}{0.0928}\n", tol).problems != []
    assert _compare_text(a, "\\newcommand{\\X}{about 0.0925}\n", tol).problems != []


def test_json_numbers_and_strings():
    ref = json.dumps({"a": 7.25, "b": "chatter", "c": [1, 2]})
    assert (
        _compare_file("figures/x.json", ref, json.dumps({"a": 7.25 * (1 + 1e-12), "b": "chatter", "c": [1, 2]})).status
        == "pass"
    )
    assert (
        _compare_file("figures/x.json", ref, json.dumps({"a": 7.25 + 1e-6, "b": "chatter", "c": [1, 2]})).status
        == "fail"
    )
    assert _compare_file("figures/x.json", ref, json.dumps({"a": 7.25, "b": "stuck", "c": [1, 2]})).status == "fail"
    assert _compare_file("figures/x.json", ref, json.dumps({"a": 7.25, "b": "chatter", "c": [1]})).status == "fail"


def test_the_table_is_stated_once_and_every_tolerance_is_below_the_failure_it_must_catch():
    assert DEFAULT.rtol * 50 < 1e-6  # a settled number (|x| <= 50) moved by 1e-6 fails by default
    for pattern, tol in TOLERANCES:
        assert tol.why, pattern
        assert 0 <= tol.max_sensitive <= 0.2, pattern


@pytest.mark.parametrize("args", [["/no/such/dir"], ["--against", "no-such-revision"]])
def test_the_command_names_a_bad_directory_or_revision(args):
    out = subprocess.run(
        [sys.executable, "-m", "impactdamper", "check-record", *args], cwd=ROOT, capture_output=True, text=True
    )
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1, out.stderr


def test_the_command_fails_on_a_wrong_record(tmp_path):
    _sweep_edited(tmp_path, "x1_max", lambda x: repr(float(x) + 1e-6))
    new, reference = tmp_path / "new", str(tmp_path / "reference")
    out = subprocess.run(
        [sys.executable, "-m", "impactdamper", "check-record", str(new), "--against", reference, "--json"],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    answer = json.loads(out.stdout)
    assert out.returncode == 1 and answer["reproduces"] is False and answer["files"][0]["status"] == "fail"


def test_a_sensitive_mark_may_come_and_go_but_a_word_may_not():
    """An interval end marked as depending on the solver (a dagger) may lose its mark on another
    machine; the same line with another word fails."""
    ref = r"$N$ & $[0.5799, 0.6169]$ \\"
    assert not _compare_text(ref, r"$N$ & $[0.5799, 0.6168^{\dagger}]$ \\", DEFAULT).problems
    assert _compare_text(ref, r"$R$ & $[0.5799, 0.6169]$ \\", DEFAULT).problems


def test_the_located_range_ends_move_by_a_bisection_step_and_no_more():
    """The located range's ends: one bisection step (7.8e-4, as measured past the BLAS pin) passes,
    ten do not; any other number of the verdict keeps the default tolerance."""
    tol = tolerance_of("figures/verdict.json")
    ref = json.dumps({"located": {"range": [-10.076171875, -9.489453125]}, "stated": {"time": 0.66220}})
    one_step = json.dumps({"located": {"range": [-10.076953125, -9.489453125]}, "stated": {"time": 0.66220}})
    ten_steps = json.dumps({"located": {"range": [-10.083984375, -9.489453125]}, "stated": {"time": 0.66220}})
    moved = json.dumps({"located": {"range": [-10.076171875, -9.489453125]}, "stated": {"time": 0.66221}})
    assert _compare_file("figures/verdict.json", ref, one_step).status == "pass"
    assert _compare_file("figures/verdict.json", ref, ten_steps).status == "fail"
    assert _compare_file("figures/verdict.json", ref, moved).status == "fail"
    assert tol.by_name
