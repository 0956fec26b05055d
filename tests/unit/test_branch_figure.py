"""Branch diagrams' drawing helpers: labels aligned away from their point, special points'
radius clipped to the axis, a NaN radius not drawn, the legend's rows."""

import math

from impactdamper.reporting.branch_figure import (
    INADMISSIBLE_MARK,
    RADIUS_LIMITS,
    label_point,
    legend_rows,
    mark_case,
    mark_special,
)
from impactdamper.reporting.plotting import use_style


def _axes():
    plt = use_style()
    fig, (ax_x, ax_r) = plt.subplots(2)
    return plt, fig, ax_x, ax_r


def test_a_label_is_aligned_away_from_its_point_and_grey_off_the_motions():
    plt, fig, ax, _ = _axes()
    label_point(ax, "PD", (1.0, 2.0), (-4, 6), on=True)
    label_point(ax, "F", (1.0, 2.0), (0, -9), on=False)
    a, b = ax.texts
    assert (a.get_ha(), a.get_va(), a.get_color()) == ("right", "bottom", "0.1")
    assert (b.get_ha(), b.get_va(), b.get_color()) == ("center", "top", INADMISSIBLE_MARK)
    plt.close(fig)


def test_a_special_point_radius_is_clipped_and_a_nan_radius_left_out():
    plt, fig, ax_x, ax_r = _axes()
    mark_special(ax_x, ax_r, -5.0, 3.0, 50.0, "fold", "C1", True, 4.5)
    mark_special(ax_x, ax_r, -4.0, 2.0, math.nan, "grazing_interior", "C1", False, 3.5)
    assert [tuple(line.get_ydata()) for line in ax_r.lines] == [(RADIUS_LIMITS[1],)]
    assert len(ax_x.lines) == 2
    assert ax_x.lines[1].get_markerfacecolor() == "white"
    plt.close(fig)


def test_a_case_is_named_only_when_asked():
    plt, fig, ax_x, ax_r = _axes()
    mark_case(ax_x, ax_r, -5.8, 3.0, 0.9, None)
    mark_case(ax_x, ax_r, -9.6, 2.0, 0.8, "located case -9.6")
    assert [t.get_text() for t in ax_x.texts] == ["located case -9.6"]
    plt.close(fig)


def test_the_legend_has_the_branches_the_kinds_and_the_window():
    rows = legend_rows([("C0", "1/1"), ("C1", "3/2")], {"fold": "fold", "period_doubling": "PD"})
    assert [h.get_label() for h in rows[0]] == ["1/1", "3/2", "stable", "unstable", "inadmissible"]
    assert [h.get_label() for h in rows[1]] == ["fold", "PD", "case"]
    assert [h.get_label() for h in rows[2]] == ["zoom window", "$|\\rho| = 1$"]
