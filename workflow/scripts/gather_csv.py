"""Gathers the chunks of a chunked sweeps-stage job into one table.

Not a figure script: concatenates the chunk CSVs in chunk order (each has the same header),
so the gathered table does not depend on how many jobs ran or in which order.
"""

from pathlib import Path

from impactdamper.reporting.records import run_stage


def main(chunks, out_csv) -> None:
    header, body = None, []
    for path in chunks:
        lines = Path(path).read_text().splitlines()
        if header is None:
            header = lines[0]
        elif lines[0] != header:
            raise ValueError(f"`{path}` has a different header: {lines[0]!r} != {header!r}")
        body.extend(lines[1:])
    Path(out_csv).parent.mkdir(parents=True, exist_ok=True)
    Path(out_csv).write_text("\n".join([header] + body) + "\n")


if __name__ == "__main__":
    run_stage(snakemake, main, "input.chunks:list output.csv")  # noqa: F821 (injected by Snakemake's script: directive)
