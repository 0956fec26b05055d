"""Lyapunov exponents of the impacting flow (workflow/rules/lyapunov.smk): the largest exponent
along the gap sweep and over a map, the labels of the points the sweeps leave nonperiodic, the
checks of the compiled spectrum, and the stage's record."""
