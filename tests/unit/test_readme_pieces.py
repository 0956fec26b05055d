"""The README's pieces: the results table, one line per row with its cells on one line, read
back by the parser the README's test uses."""

import pytest

from helpers import parse_results_table

from impactdamper.reporting.readme import RESULTS_HEADER, results_table


def test_the_results_table_has_its_header_and_one_line_per_row():
    lines = results_table([("a claim", "**not reproduced**", "x | y\n  z", "Reproduction")])
    assert lines[0] == "| claim or question | verdict or answer | evidence | in the report |"
    assert lines[1] == "|---|---|---|---|"
    assert lines[2] == "| a claim | **not reproduced** | x \\| y z | Reproduction |"


def test_the_results_table_reads_back():
    rows = [("a", "b", "c | d", "e"), ("f", "g", "h", "i")]
    parsed = parse_results_table("text\n\n" + "\n".join(results_table(rows)) + "\n\nmore")
    assert [tuple(r[k] for k in RESULTS_HEADER) for r in parsed] == rows


def test_a_row_of_the_wrong_length_is_refused():
    with pytest.raises(ValueError, match="`rows` has a row of 3 cells"):
        results_table([("a", "b", "c")])
    with pytest.raises(ValueError, match="no results table"):
        parse_results_table("| x | y |\n|---|---|")
