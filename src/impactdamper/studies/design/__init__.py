"""Choosing a suppressor (workflow/rules/design.smk): linear baselines, design charts, both
devices' optima, and the stage's record."""
