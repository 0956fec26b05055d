"""Both of the paper's Fig. 2 claims at many points near the stated set, and whether a point
reproduces them robustly: the points as relative changes u of the seven relative parameters,
their norms, the claims evaluated (cached, in worker processes) and the margin's offsets.

Timofeev, Lyuminarskiy & Lyuminarskiy (2019), DOI 10.18698/0236-3941-2019-1-90-100: claim (a)
Algorithm No. 1 (eqs. 7-17) gives a negative gap on (t1, t2); claim (b) Algorithm No. 2, from
its step 1, settles to T_c = 2T with three impacts. What the nearest reproducing set
(:mod:`impactdamper.studies.claims.nearest`) and the round values
(:mod:`impactdamper.studies.claims.round_changes`) search with.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from impactdamper import steady_states
from impactdamper.analysis.parallel import map_blocks
from impactdamper.analysis.point import SweepSettings
from impactdamper.core.algorithm1 import algorithm1
from impactdamper.core.parameters import RELATIVE_PARAMETERS, Parameters
from impactdamper.studies.replication.claims import CLAIM_B_IMPACTS, CLAIM_B_PERIOD_MULTIPLE, claim_a
from impactdamper.studies.vocabulary import SPEC

__all__ = ["NEAREST_NAMES", "NORMS", "ClaimsEvaluator", "norm", "ball_offsets", "robust"]

# Fewest points a worker process is given (a point costs one to a few milliseconds).
MIN_BLOCK = 16
# The seven relative parameters searched, in this order (u's components).
NEAREST_NAMES = RELATIVE_PARAMETERS
NORMS = ("max", "euclidean")


def norm(u: np.ndarray, which: str) -> np.ndarray:
    """The max-norm or Euclidean norm of relative changes ``u`` (shape (..., 7))."""
    u = np.asarray(u, float)
    if which == "max":
        return np.max(np.abs(u), axis=-1)
    if which == "euclidean":
        return np.sqrt(np.sum(u * u, axis=-1))
    raise ValueError(f"`norm` = {which!r} is not allowed: must be one of {', '.join(NORMS)}")


@dataclass
class ClaimsEvaluator:
    """Both claims at many points u (relative changes of :data:`NEAREST_NAMES` from ``base``).

    Claim (a) by Algorithm No. 1 (closed form, ``gap_tol``), claim (b) by the compiled batch
    with ``settings``, each point from the paper's step 1, evaluated only where (a) holds (both
    are needed); both in ``workers`` processes (:func:`impactdamper.analysis.parallel.map_blocks`,
    the batch's own workers: the same flags). ``points`` counts the points evaluated,
    ``batch_points`` those simulated.
    """

    base: Parameters
    gap_tol: float
    settings: SweepSettings
    workers: int = 1
    points: int = 0
    batch_points: int = 0
    _cache: dict = field(default_factory=dict)

    @property
    def stated(self) -> np.ndarray:
        return np.array([getattr(self.base, n) for n in NEAREST_NAMES], float)

    def values(self, U: np.ndarray) -> np.ndarray:
        """Absolute values x = stated (1 + u), shape (P, 7)."""
        return self.stated * (1.0 + np.asarray(U, float).reshape(-1, len(NEAREST_NAMES)))

    def valid(self, X: np.ndarray) -> np.ndarray:
        """Whether each point is in every parameter's domain (Parameters' own ranges): a point
        outside one is no reproduction, never an error."""
        return np.array([all(SPEC[n].ok(float(v)) for n, v in zip(NEAREST_NAMES, x)) for x in X], bool)

    def __call__(self, U) -> tuple[np.ndarray, np.ndarray]:
        """(claim_a, claim_b) flags, shape (P,) each (claim_b False where claim_a is)."""
        U = np.asarray(U, float).reshape(-1, len(NEAREST_NAMES))
        keys = [tuple(np.round(u, 13)) for u in U]
        todo = sorted({k for k in keys if k not in self._cache})
        if todo:
            X = self.values(np.array(todo))
            ok = self.valid(X)
            fa = np.zeros(len(todo), bool)
            valid = np.flatnonzero(ok)
            fa[valid] = map_blocks(self._claim_a, [X[i] for i in valid], self.workers, MIN_BLOCK)
            fb = np.zeros(len(todo), bool)
            idx = np.flatnonzero(fa)
            if len(idx):
                workers = self.workers if len(idx) >= 2 * MIN_BLOCK else 1
                res = steady_states(
                    self.base, NEAREST_NAMES, X[idx], settings=self.settings, chain=False, workers=workers
                )
                fb[idx] = (
                    (res.regime == "multi_impact")
                    & (res.period_multiple == CLAIM_B_PERIOD_MULTIPLE)
                    & (res.impacts_per_cycle == CLAIM_B_IMPACTS)
                )
            self.points += len(todo)
            self.batch_points += len(idx)
            for k, a, b in zip(todo, fa, fb):
                self._cache[k] = (bool(a), bool(b))
        fa = np.array([self._cache[k][0] for k in keys], bool)
        fb = np.array([self._cache[k][1] for k in keys], bool)
        return fa, fb

    def both(self, U) -> np.ndarray:
        fa, fb = self(U)
        return fa & fb

    def _claim_a(self, X: list) -> list[bool]:
        """Claim (a) at absolute values ``X`` (rows of :data:`NEAREST_NAMES`)."""
        out = []
        for x in X:
            p = self.base.replace(**dict(zip(NEAREST_NAMES, map(float, x))))
            out.append(bool(claim_a(algorithm1(p, gap_tol=self.gap_tol))))
        return out


def ball_offsets(margin: float, which: str, random_points: int = 0, seed: int = 0) -> np.ndarray:
    """Offsets of a margin check: the centre, the 14 axis points +-margin e_i and
    ``random_points`` random points on the ball's surface (the Euclidean sphere; for the
    max-norm the cube's surface, half of them at its vertices, where it reaches farthest)."""
    d = len(NEAREST_NAMES)
    out = [np.zeros(d)] + [s * margin * e for e in np.eye(d) for s in (1.0, -1.0)]
    rng = np.random.default_rng([int(seed), d])
    for j in range(int(random_points)):
        if which == "euclidean":
            v = rng.normal(size=d)
            out.append(margin * v / np.linalg.norm(v))
        elif j % 2 == 0:
            out.append(margin * rng.choice([-1.0, 1.0], size=d))
        else:
            v = rng.uniform(-1.0, 1.0, size=d)
            v[rng.integers(d)] = rng.choice([-1.0, 1.0])
            out.append(margin * v)
    return np.array(out)


def robust(ev: ClaimsEvaluator, U: np.ndarray, margin: float) -> np.ndarray:
    """Both claims at each point of ``U`` and at its 14 axis points +-margin e_i."""
    U = np.asarray(U, float).reshape(-1, len(NEAREST_NAMES))
    off = ball_offsets(margin, "euclidean")
    flags = ev.both((U[:, None, :] + off[None, :, :]).reshape(-1, U.shape[1]))
    return flags.reshape(len(U), len(off)).all(axis=1)
