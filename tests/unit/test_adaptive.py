"""Maps computed where the picture changes (impactdamper.analysis.adaptive) against the brute
force: a cell settled from its left neighbour's carried section is the chained sweep's cell bit
for bit; the brute force (every cell, coarse_step 1) is one chained sweep per row; a coarser one differs from it only in a
measured share of cells, next to a change of label; the quadtree of independent cells computes
both ends of every boundary it is to resolve and fills the rest from agreeing corners."""

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.analysis.adaptive import (
    adaptive_regime_map,
    coarse_indices,
    fill_blocks,
    label_differences,
    refine_lattice,
)
from impactdamper.analysis.ladder import carry_state
from impactdamper.analysis.parallel import map_blocks
from impactdamper.analysis.point import SweepSettings
from impactdamper.core.model import FREE, STUCK

REF = idp.Parameters()
# The regime maps' settings (config/config.yaml, maps).
MAPS = SweepSettings(
    settle_tol=1e-9, max_periods=300, max_periods_after_nonperiodic=300, max_period_multiple=8, continuation=False
)


def test_a_cell_settled_from_its_carried_neighbour_is_the_chained_sweeps_cell_bit_for_bit():
    """The claim the adaptive map rests on: settling cell j alone from carry_state(section of
    cell j - 1) is what the chained batch does (start, section, label, periods, rescue)."""
    gaps = np.linspace(-11.0, -5.0, 10)
    values = np.column_stack([gaps, np.full(len(gaps), 1.0)])
    chained = idp.steady_states(REF, ("gap", "theta"), values, settings=MAPS)
    assert len(set(chained.label)) >= 3  # the row crosses changes of motion
    for j in range(1, len(gaps)):
        p = REF.replace(gap=float(gaps[j]))
        start, _ = carry_state(p, chained.sections[j - 1], STUCK if chained.section_modes[j - 1] == 1 else FREE)
        alone = idp.steady_states(REF, ("gap", "theta"), values[j : j + 1], settings=MAPS, chain=False, states=[start])
        assert np.array_equal(alone.start_states[0], chained.start_states[j]), j
        assert np.array_equal(alone.sections[0], chained.sections[j]), j
        assert (alone.label[0], alone.periods[0], alone.method[0]) == (
            chained.label[j],
            chained.periods[j],
            chained.method[j],
        ), j


@pytest.mark.parametrize("options", [dict(brute_force=True), dict(coarse_step=1)])
def test_the_brute_force_is_each_row_one_chained_sweep(options):
    """brute_force (and coarse_step 1) settles every cell, and each row is the chained sweep of
    one steady_states call per row, bit for bit."""
    gaps, thetas = np.linspace(-12.0, -4.0, 18), [0.9, 1.0]
    m = adaptive_regime_map(REF, "gap", gaps, "theta", thetas, settings=MAPS, **options)
    assert m.computed.all() and m.settlings == m.computed.size
    for r, theta in enumerate(thetas):
        row = idp.steady_states(
            REF, ("gap", "theta"), np.column_stack([gaps, np.full(len(gaps), theta)]), settings=MAPS
        )
        assert list(m.label[r]) == list(row.label)
        assert np.array_equal(m.periods[r], row.periods) and np.array_equal(m.x1_max[r], row.x1_max, equal_nan=True)


@pytest.mark.slow
@pytest.mark.parametrize("direction", ["up", "down"])
def test_adaptive_regime_map_against_the_brute_force(direction):
    """A 12 x 160 piece of the theta map (Delta0/x_st -40..15 across every regime, theta near
    resonance where motions coexist): settled where the labels change, a quarter of the cells or
    fewer; the labels the brute force's but in at most 1 % of the cells, each next to a change of
    the brute force's labels or inside a window narrower than the coarse step."""
    gaps, thetas = np.linspace(-40.0, 15.0, 160), np.linspace(0.9, 1.1, 12)
    brute = adaptive_regime_map(REF, "gap", gaps, "theta", thetas, direction=direction, settings=MAPS, brute_force=True)
    brute = brute.label
    m = adaptive_regime_map(REF, "gap", gaps, "theta", thetas, direction=direction, settings=MAPS, coarse_step=8)
    d = label_differences(m.label, brute, rows=range(len(thetas)))
    assert m.computed_share < 0.45, m.computed_share
    assert d["share"] <= 0.01, d
    assert d["max_distance"] < 8, d
    # Every change of label is between two settled neighbours: nothing is filled across it.
    for r in range(len(thetas)):
        change = np.flatnonzero(m.label[r, :-1] != m.label[r, 1:])
        assert m.computed[r, change].all() and m.computed[r, change + 1].all(), r


def test_bad_direction_and_step_are_named():
    with pytest.raises(ValueError, match="^`direction` = 'left' is not allowed"):
        adaptive_regime_map(REF, "gap", [-6.0, -5.0], "theta", [1.0], direction="left")
    with pytest.raises(ValueError, match="^`coarse_step` = 0 is not allowed"):
        coarse_indices(5, 0)


# --- independent cells: the quadtree ---------------------------------------------------------------
def _disc(i: int, j: int) -> str:
    """A label on a 33 x 33 lattice: a disc of one label, a thin ring of another, the rest a third."""
    r2 = (i - 16) ** 2 + (j - 14) ** 2
    return "in" if r2 < 81 else "ring" if r2 < 100 else "out"


@pytest.mark.parametrize("step", [4, 8])
def test_quadtree_resolves_every_boundary_its_corners_see_and_fills_the_rest_from_them(step):
    n = 33
    calls = []

    def evaluate(points):
        calls.append(len(points))
        return [_disc(i, j) for i, j in points]

    idx = coarse_indices(n, step)
    known = {(i, j): _disc(i, j) for i in idx for j in idx}
    blocks = [(a, b, c, d) for a, b in zip(idx, idx[1:]) for c, d in zip(idx, idx[1:])]
    known, final, stats = refine_lattice(known, blocks, evaluate, lambda keys: len(set(keys)) > 1)
    filled = fill_blocks(known, final)
    assert len(known) + len(filled) == n * n and not set(known) & set(filled)
    assert stats["points_per_round"] == calls and len(known) < 0.6 * n * n
    assert all(known[ij] == _disc(*ij) for ij in known)
    # A filled cell takes its block's corners' label; it is wrong only inside a block whose
    # four corners agree while the ring passes between them (counted, and few).
    wrong = [ij for ij, key in filled.items() if key != _disc(*ij)]
    assert len(wrong) <= 0.01 * n * n
    for i0, i1, j0, j1 in final:
        corners = {known[(i0, j0)], known[(i1, j0)], known[(i0, j1)], known[(i1, j1)]}
        assert len(corners) == 1 or (i1 - i0 <= 1 and j1 - j0 <= 1)


def test_label_differences_measures_the_distance_to_the_nearest_change():
    ref = np.array([["a"] * 5 + ["b"] * 5, ["a"] * 10], dtype=object)
    got = ref.copy()
    got[0, 4] = "b"  # next to the change
    got[1, 9] = "c"  # a row without changes: the row's width
    d = label_differences(got, ref, rows=[0, 1])
    assert d["differences"] == 2 and d["cells"] == 20 and d["share"] == 0.1
    assert d["distances"] == [1, 10] and d["max_distance"] == 10
    d2 = label_differences(got, ref)  # both directions: row 1's cell is 1 below row 0's b
    assert d2["distances"] == [1, 1]
    with pytest.raises(ValueError, match="^`labels` of shape"):
        label_differences(got[:1], ref)


def test_label_differences_split_filled_cells_from_computed_ones():
    # A filled cell that differs is the fill's error; a computed one, history (another start).
    ref = np.array([["a"] * 5 + ["b"] * 5, ["a"] * 10], dtype=object)
    got = ref.copy()
    got[0, 4], got[1, 9], got[1, 2] = "b", "c", "c"
    computed = np.zeros(ref.shape, dtype=bool)
    computed[:, ::4] = True  # cells 0, 4, 8 computed: (0, 4) is computed, (1, 9) and (1, 2) filled
    d = label_differences(got, ref, rows=[0, 1], computed=computed)
    assert (d["differences"], d["computed_differences"], d["filled_differences"]) == (3, 1, 2)
    assert "filled_differences" not in label_differences(got, ref, rows=[0, 1])


# --- independent pieces of work in forked processes -----------------------------------------------
def test_map_blocks_gives_the_serial_result_in_order_with_a_closure():
    offset = 7  # (a closure: inherited by the forked workers, never pickled)
    items = list(range(23))
    serial = map_blocks(lambda xs: [x * x + offset for x in xs], items)
    assert serial == [x * x + offset for x in items]
    assert map_blocks(lambda xs: [x * x + offset for x in xs], items, workers=3) == serial
    assert map_blocks(lambda xs: [len(xs)], items, workers=2, min_block=20) == [23]  # too few to split
    assert map_blocks(lambda xs: list(xs), [], workers=2) == []
    with pytest.raises(ValueError, match="^`workers` = 0 is not allowed"):
        map_blocks(list, items, workers=0)
