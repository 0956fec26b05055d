"""One chunk of a regime map (impactdamper.studies.sweeps.mapchunk): the rows dealt to the chunks
in turn cover the map once, the brute force's rows are each chunk's every check_every-th, and a
chunk's record puts each cell's label where the brute force finds it, but for the cells its check
counts."""

import numpy as np
import pytest

from impactdamper.analysis.adaptive import adaptive_regime_map
from impactdamper.studies.config import parameters, sweep_settings
from impactdamper.studies.sweeps.gapsweep import map_axes
from impactdamper.studies.sweeps.mapchunk import CHUNK_COLUMNS, check_rows, _chunk_rows, regime_map_chunk
from tests.helpers import shipped_config


@pytest.mark.parametrize(("rows", "chunks"), [(7, 1), (7, 2), (400, 4), (3, 4)])
def test_the_chunks_deal_every_row_once(rows, chunks):
    dealt = np.concatenate([_chunk_rows(rows, chunks, c) for c in range(chunks)])
    assert sorted(dealt.tolist()) == list(range(rows))


def test_a_chunk_outside_the_map_is_refused():
    with pytest.raises(ValueError, match="`chunk` = 4 is not allowed: must be in \\[0, 4\\)"):
        _chunk_rows(10, 4, 4)


def test_each_chunk_checks_every_check_every_th_row_from_its_own_first():
    # The record's setting: 400 rows, 4 chunks, check_every 40: rows c, c + 40, ... of chunk c.
    for c in range(4):
        own = _chunk_rows(400, 4, c)
        assert own[check_rows(len(own), 40, 4)].tolist() == list(range(c, 400, 40))
    assert check_rows(100, 0, 4) == []


def test_a_chunks_cells_sit_where_the_brute_force_finds_their_labels():
    cfg = shipped_config()
    maps = dict(cfg["maps"], chunks=2, check_every=2, coarse_step=4)
    maps["theta"] = dict(maps["theta"], start=0.9, stop=1.1, points=4, gap_start=-12.0, gap_stop=-4.0, gap_points=17)
    rows, counts, timer = regime_map_chunk(cfg["reference"], cfg["solver"], maps, "theta", 1)
    assert len(rows) == 2 * 17 and all(list(r) == CHUNK_COLUMNS for r in rows)
    assert sorted({r["i"] for r in rows}) == [1, 3] and counts["rows"] == 2 and counts["cells"] == 34
    assert counts["check"]["rows"] == [1, 3] and counts["check"]["cells"] == 34  # every row checked
    assert 0 < counts["computed"] < 34 and timer.wall > 0.0
    # The brute force, again: each cell's label against the one the record put at (i, j).
    slow, slow_values, gaps = map_axes(maps, "theta")
    settings = sweep_settings(maps, cfg["solver"], continuation=False, rescue=bool(maps["rescue"]))
    brute = adaptive_regime_map(
        parameters(cfg["reference"]), "gap", gaps, slow, slow_values[[1, 3]], settings=settings, brute_force=True
    )
    expected = {(i, j): brute.label[r, j] for r, i in enumerate((1, 3)) for j in range(17)}
    differ = sum(r["label"] != expected[(r["i"], r["j"])] for r in rows)
    assert differ == counts["check"]["differences"]
    assert len({r["label"] for r in rows}) > 1  # a change of label inside: the placement is tested
