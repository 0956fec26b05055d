"""The figures' signs: a negative number in a figure's text is typeset with a minus sign
(U+2212), as the report's text and matplotlib's tick labels are; hyphens stay hyphens."""

import pytest

from impactdamper.reporting.plotting import _typeset_minus

MINUS = "\u2212"


@pytest.mark.parametrize(
    "text, expected",
    [
        ("located case -9.6", f"located case {MINUS}9.6"),
        ("(-9.529, -9.430)", f"({MINUS}9.529, {MINUS}9.430)"),
        ("x = -.5", f"x = {MINUS}.5"),
        ("one-impact motion", "one-impact motion"),  # a hyphen in a word
        ("theta 0.5-1.5", "theta 0.5-1.5"),  # a range
        ("4/2 (-> np)", "4/2 (-> np)"),  # an arrow
        ("$\\Delta_0 = -5.8$, stated -5.8", f"$\\Delta_0 = -5.8$, stated {MINUS}5.8"),  # mathtext makes its own
    ],
)
def test_negative_numbers_get_a_minus_sign(text, expected):
    assert _typeset_minus(text) == expected


def test_finish_figure_typesets_every_text(tmp_path):
    from impactdamper.reporting.plotting import finish_figure, use_style

    plt = use_style()
    fig, ax = plt.subplots()
    ax.set_title("stated case -5.8")
    ax.plot([0, 1], [0, 1], label="gap -9.6")
    legend = ax.legend()
    finish_figure(fig, tmp_path / "f.png")
    assert ax.get_title() == f"stated case {MINUS}5.8"
    assert legend.get_texts()[0].get_text() == f"gap {MINUS}9.6"
