"""The studies the workflow's stages run, one room (subpackage) per stage of the workflow
(``workflow/rules/<stage>.smk``), each with its study and its record for the report:

* :mod:`~impactdamper.studies.replication` (``reference.smk``): the paper's claims about its
  Fig. 2, the cases, the independent cross-checks, the gap scan, other readings, the verdict;
* :mod:`~impactdamper.studies.claims` (``claims.smk``): where the claims hold beyond the gap
  (one parameter at a time, pair maps, the nearest set in all seven at once);
* :mod:`~impactdamper.studies.sweeps` (``sweeps.smk``, ``orbits.smk``): the gap sweep, its
  transitions checked a second way, the regime maps' results, the periodic orbits' branches;
* :mod:`~impactdamper.studies.design` (``design.smk``): choosing a suppressor;
* :mod:`~impactdamper.studies.performance` (``performance.smk``): the methods, the hard cases,
  work-precision, the compiled solver's speed.

Shared by the rooms: :mod:`~impactdamper.studies.config` (the library's objects from the
config's sections), :mod:`~impactdamper.studies.intervals` (where a predicate holds along one
parameter) and :mod:`~impactdamper.studies.vocabulary` (the parameters' symbols and names).
"""

__all__ = ["STAGE_ROOMS"]

# Each stage of the workflow (``workflow/rules/<stage>.smk``) and its room, the subpackage its
# scripts import (docs/ARCHITECTURE.md quotes it as a table; tests/workflow/test_architecture.py
# holds the two together and each stage's scripts to their room).
STAGE_ROOMS = {
    "reference": "replication",
    "claims": "claims",
    "sweeps": "sweeps",
    "orbits": "sweeps",
    "design": "design",
    "lyapunov": "lyapunov",
    "performance": "performance",
    "report": "performance",
}
