"""The gap sweep and the periodic orbits (workflow/rules/sweeps.smk, orbits.smk): sweep grids and
rows, transitions checked a second way, the regime maps' results, orbit branches, and the two
stages' records."""
