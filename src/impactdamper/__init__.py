"""impactdamper: exact calculation of impact vibration suppressors of unilateral action.

A replication and extension of G.A. Timofeev, I.E. Lyuminarskiy, S.E. Lyuminarskiy,
"Calculation of shock vibration suppressors of unilateral action", Herald of the Bauman Moscow
State Technical University, Series Mechanical Engineering, 2019, no. 1, pp. 90-100,
DOI 10.18698/0236-3941-2019-1-90-100.

Public API
----------
Parameters          the paper's relative parameters (defaults: the reference case of Fig. 2)
algorithm1(p)       Algorithm No. 1, the closed-form one-impact orbit, eqs. (7)-(17)
simulate(p, t_end)  Algorithm No. 2 with the exact flow, contact modes and grazing
steady_state(p)     the settled motion: period, impacts, regime (attractor=True: Algorithm No. 1's
                    orbit where it is an attractor, no transient)
steady_states(base, names, values)  settled motions at many points: sweeps, grids, map rows,
                    random starts, many independent chains (chain_length=), in parallel (workers=)
lyapunov_spectrum(p)  the Lyapunov spectrum of the motion: exponents with errors, its label
                    (chaotic, quasi-periodic, periodic, not settled)
                    (each with backend="auto" | "compiled" | "python"; see analysis/solve.py)
solve_orbit(p)      a periodic cycle solved directly: admissibility, Floquet multipliers
continue_orbit(o)   a branch of cycles in one parameter: folds, period doublings, grazing
"""

from impactdamper.core.algorithm1 import Algorithm1Result, algorithm1
from impactdamper.core.parameters import REFERENCE, Parameters
from impactdamper.core.simulate import EventDrivenSolver, Tolerances, default_initial_state
from impactdamper.core.trajectory import Event, Trajectory
from impactdamper.core.settled_cycle import REGIMES, CycleImpact, SteadyState
from impactdamper.analysis.branch import Branch, BranchPoint, SpecialPoint
from impactdamper.analysis.continuation import continue_orbit
from impactdamper.analysis.cycle import PeriodicOrbit
from impactdamper.analysis.orbits import OrbitError, orbit_from_cycle, solve_orbit
from impactdamper.analysis.lyapunov import LyapunovSpectrum
from impactdamper.analysis.solve import BACKENDS, lyapunov_spectrum, simulate, steady_state, steady_states

__version__ = "0.1.0"

__all__ = [
    "Parameters",
    "REFERENCE",
    "algorithm1",
    "Algorithm1Result",
    "simulate",
    "Trajectory",
    "Event",
    "EventDrivenSolver",
    "Tolerances",
    "default_initial_state",
    "steady_state",
    "steady_states",
    "BACKENDS",
    "lyapunov_spectrum",
    "LyapunovSpectrum",
    "SteadyState",
    "CycleImpact",
    "REGIMES",
    "solve_orbit",
    "orbit_from_cycle",
    "continue_orbit",
    "PeriodicOrbit",
    "Branch",
    "BranchPoint",
    "SpecialPoint",
    "OrbitError",
]
