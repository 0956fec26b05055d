"""Region labels on a regime map: each large region labelled once, at a cell of its own, small
regions and labels crowding one already written left out."""

import numpy as np

from impactdamper.reporting.plotting import label_bands, label_regions, use_style


def _texts(labels, slow, gaps):
    plt = use_style()
    fig, ax = plt.subplots()
    label_regions(ax, slow, gaps, labels, lambda lab: "stuck" if lab == "stuck" else "single_impact")
    out = [(t.get_text(), t.get_position()) for t in ax.texts]
    plt.close(fig)
    return out


def test_each_large_region_is_labelled_inside_itself_and_small_ones_are_not():
    labels = np.full((40, 40), "1/1", dtype=object)
    labels[:, 20:] = "stuck"
    labels[0:2, 0:2] = "2/1"  # 4 cells: the least (REGION_LABEL_CELLS) on 1600 cells
    labels[10, 10] = "3/1"  # one cell: too small
    slow, gaps = np.linspace(0.5, 1.5, 40), np.linspace(-40.0, 15.0, 40)
    texts = dict(_texts(labels, slow, gaps))
    assert "3/1" not in texts
    assert set(texts) == {"1/1", "S", "2/1"}
    for text, (x, y) in texts.items():
        j, i = int(np.argmin(abs(gaps - x))), int(np.argmin(abs(slow - y)))
        assert labels[i, j] == {"S": "stuck"}.get(text, text)


def test_a_label_crowding_a_larger_one_is_left_out():
    labels = np.full((40, 40), "1/1", dtype=object)
    labels[16:24, 19] = "2/1"  # 8 cells
    labels[16:22, 20] = "4/2"  # 6 cells, one column beside: its label would overlap 2/1's
    slow, gaps = np.linspace(0.5, 1.5, 40), np.linspace(-40.0, 15.0, 40)
    texts = [t for t, _ in _texts(labels, slow, gaps)]
    assert texts[0] == "1/1"  # the largest first
    assert "4/2" not in texts


def test_a_band_label_is_written_where_it_fits_upright_on_a_narrow_band_and_not_on_a_sliver():
    plt = use_style()
    fig, ax = plt.subplots(figsize=(4.0, 1.0))
    ax.set_xlim(0.0, 100.0)
    ax.set_ylim(-0.5, 0.5)
    fig.canvas.draw()
    bands = [(40.0, 80.0, "stuck"), (85.0, 6.0, "1/1"), (95.0, 0.01, "2/1")]
    label_bands(ax, 0.0, bands, fig.canvas.get_renderer(), lambda lab: "single_impact", 0.8, {"stuck": "S"})
    texts = {t.get_text(): t.get_rotation() for t in ax.texts}
    plt.close(fig)
    assert texts == {"S": 0.0, "1/1": 90.0}
