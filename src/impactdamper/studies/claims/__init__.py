"""Where the paper's Fig. 2 claims hold beyond the stated gap (workflow/rules/claims.smk): each
parameter alone, pairs on maps, the nearest set in all seven at once, and the stage's record."""
