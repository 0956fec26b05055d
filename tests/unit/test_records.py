"""The records a workflow job writes (impactdamper.reporting.records)."""

import json

from impactdamper.reporting.records import Timer, read_csv, write_chunk, write_csv


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
