"""The records a workflow job writes (impactdamper.reporting.records)."""

import json
import statistics

import pytest

from impactdamper.reporting.records import Timer, paired_cpu_ratios, read_csv, write_chunk, write_csv


def test_write_chunk_writes_the_rows_as_write_csv_and_the_timing_with_its_counts(tmp_path):
    rows = [{"a": 1, "b": True}, {"a": 2.5, "b": False}]
    with Timer() as timer:
        pass
    timing = write_chunk(
        tmp_path / "c.csv", ["a", "b"], rows, tmp_path / "t.json", timer, booleans="digits", chunk=3, rows=len(rows)
    )
    write_csv(tmp_path / "ref.csv", ["a", "b"], rows, booleans="digits")
    assert (tmp_path / "c.csv").read_bytes() == (tmp_path / "ref.csv").read_bytes()
    assert read_csv(tmp_path / "c.csv") == [{"a": "1", "b": "1"}, {"a": "2.5", "b": "0"}]
    assert json.loads((tmp_path / "t.json").read_text()) == json.loads(json.dumps(timing))
    assert (timing["chunk"], timing["rows"]) == (3, 2)
    assert timing["wall_s"] == timer.wall and timing["cpu_s"] == timer.cpu
    assert "start_epoch" not in timing and "machine" in timing
    epochs = write_chunk(tmp_path / "d.csv", ["a"], rows, tmp_path / "u.json", timer, epochs=True, cells=4)
    assert (epochs["start_epoch"], epochs["end_epoch"], epochs["cells"]) == (timer.epoch0, timer.epoch1, 4)


class _Machine:
    """A fake process clock: a call of ``base`` costs 1 unit and of ``other`` 20, times the
    machine's slowness, which doubles after ``calls_before_load`` calls (another job starts)."""

    def __init__(self, calls_before_load: int):
        self.now, self.calls, self.calls_before_load = 0.0, 0, calls_before_load

    def spend(self, units: float):
        self.calls += 1
        self.now += units * (2.0 if self.calls > self.calls_before_load else 1.0)
        return units


def test_paired_ratios_do_not_see_a_load_that_changes_between_blocks():
    m = _Machine(calls_before_load=6)
    out = paired_cpu_ratios(lambda: m.spend(1.0), lambda: m.spend(20.0), 5, clock=lambda: m.now)
    assert out["result"] == 20.0 and len(out["ratios"]) == 5 and len(out["base_cpu_s"]) == 10
    # Every pair wholly before or wholly after the load reads 20 (one pair straddles it: 2 x 20 / 1.5).
    assert sorted(out["ratios"]) == pytest.approx([20.0, 20.0, 20.0, 20.0, 80.0 / 3.0])
    assert out["median"] == pytest.approx(20.0)
    # Two blocks timed one after the other (the base's before the load, the other's after it)
    # read 40: the estimate the pairs replace.
    blocks = _Machine(calls_before_load=6)
    base = [blocks.spend(1.0) * (2.0 if blocks.calls > 6 else 1.0) for _ in range(5)]
    other = [blocks.spend(20.0) * (2.0 if blocks.calls > 6 else 1.0) for _ in range(5)]
    assert statistics.median(other) / statistics.median(base) == pytest.approx(40.0)


def test_paired_ratios_refuse_a_bad_repeat_count():
    for bad in (0, 1.5, True):
        with pytest.raises(ValueError, match="`repeats`"):
            paired_cpu_ratios(lambda: 0, lambda: 0, bad)
