"""The README's pieces: one parameter's claim interval in words, and a cycle's impact table."""

from impactdamper.reporting.readme import beyond, impact_table


def _claims(**kw):
    m = {
        "ClaimsNNearestBoth": "0.41",
        "ClaimsNStated": "0.5",
        "ClaimsNBothOpen": "no",
        "ClaimsNBothLo": "0.38",
        "ClaimsNBothHi": "0.44",
        "ClaimsNBothWidth": "0.06",
        "ClaimsNRelDistance": "18",
    }
    return {**m, **kw}


def test_a_parameter_interval_is_named_with_its_ends_and_distance():
    assert beyond(_claims(), "N", "N") == "N in [0.38, 0.44] (width 0.06; stated 0.5, 18 % away)"
    assert "reaching the end of the searched range" in beyond(_claims(ClaimsNBothOpen="yes"), "N", "N")


def test_a_parameter_without_an_interval_says_nowhere():
    assert beyond(_claims(ClaimsNNearestBoth="–"), "N", "N") == "N: nowhere in the searched range (stated 0.5)"


def test_the_impact_table_has_one_row_per_impact_rounded(tmp_path):
    csv = tmp_path / "impacts.csv"
    csv.write_text(
        "impact,t_over_T,phase,velocity_rel,impulse_rel,next_cycle\n1,0,0.123456,1.23456,0.654321,false\n"
        "1,2,0.123457,1.23456,0.654321,true\n"
    )
    lines = impact_table(str(csv))
    assert len(lines) == 4
    assert lines[2] == "| 1 | 0.0000 | 0.1235 | 1.235 | 0.6543 |"
    assert lines[3].startswith("| 1 (next cycle) | 2.0000 |")
