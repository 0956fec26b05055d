"""The replication of the paper's Fig. 2 (workflow/rules/reference.smk): the claims, the cases, the
independent cross-checks, the gap scan, other readings of the paper, the verdict and its record."""
