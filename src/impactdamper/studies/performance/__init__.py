"""The solvers' performance (workflow/rules/performance.smk): the methods' table, work-precision,
the hard cases, the compiled solver's speed, and the stage's record."""
