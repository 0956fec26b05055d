"""The stitched motion of Algorithm No. 2: its events and its piecewise-exact trajectory.

A run of the event-driven loop (:mod:`impactdamper.core.simulate`, or the compiled kernels) is
a sequence of segments, each the exact flow of one contact mode from its start state
(:class:`~impactdamper.core.events.Segment`), with the events between them: impacts
(eqs. 21-22), captures into persistent contact and lift-offs. :class:`Trajectory` stitches them
and samples the state at any time; a compiled run keeps its arrays and makes the objects when
they are first read. :func:`rescale_trajectory` carries a motion to other free scales.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from impactdamper.core.events import Segment
from impactdamper.core.model import FREE, STUCK, Model, model_of
from impactdamper.core.parameters import ScaleMap

__all__ = ["Event", "Trajectory", "EVENT_KINDS", "MODE_NAMES", "rescale_trajectory"]


@dataclass(frozen=True)
class Event:
    """One event of the motion.

    Attributes
    ----------
    t : float
        Time, s.
    kind : str
        ``"impact"`` (eqs. 21-22), ``"stick"`` (capture into persistent contact) or
        ``"liftoff"`` (contact force reached zero).
    velocity : float
        Closing relative velocity x2' - x1' just before an impact, m/s (0 for other kinds).
    impulse : float
        Pulse S, N s (for ``stick``: the plastic pulse that cancels the rebound).
    before, after : ndarray, shape (4,)
        State (x1, x2, x1', x2') just before and after.
    t_accumulation : float
        For ``stick``: estimated end of the accumulation of impacts it replaces (Budd & Dux);
        equal to t otherwise.
    """

    t: float
    kind: str
    velocity: float
    impulse: float
    before: np.ndarray = field(repr=False)
    after: np.ndarray = field(repr=False)
    t_accumulation: float = float("nan")


# Event kinds and contact modes by code: how a compiled run's arrays name them (the kernels'
# codes index these; core/compiled/layout.py).
EVENT_KINDS = ("impact", "stick", "liftoff")
MODE_NAMES = (FREE, STUCK)


class Trajectory:
    """The piecewise-exact motion: segments of one mode each, and the events between them.

    ``backend`` says what computed it (``python``: this solver; ``compiled``: the numba
    kernels), ``fallback`` why the Python solver ran where the kernels were asked ("" otherwise).
    A compiled run (:meth:`from_arrays`) keeps the kernels' arrays and makes its
    :class:`Event` and :class:`~impactdamper.core.events.Segment` objects when they are first read
    (a segment when a time in it is sampled): a long run costs no Python object per event until
    one is asked for."""

    def __init__(self, model: Model, backend: str = "python", fallback: str = ""):
        self.model = model
        self.backend = backend
        self.fallback = fallback
        self._segments: list[tuple[str, Segment]] = []
        self._events: list[Event] = []
        self._arrays = None  # a compiled run's (kinds, events, segment modes, segments) not yet made into objects
        self._made: dict[int, tuple[str, Segment]] = {}  # its segments made so far, by index

    @classmethod
    def from_arrays(
        cls, model: Model, kinds, events, segment_modes, segments, *, backend: str = "compiled", fallback: str = ""
    ) -> Trajectory:
        """A run from a compiled kernel's arrays: event kinds (E,) indexing :data:`EVENT_KINDS`;
        events (E, 12): t, closing velocity, pulse, state before (4), after (4), accumulation
        time; segment modes (S,) indexing :data:`MODE_NAMES`; segments (S, 5): start time and
        start state (4; stuck: x1, x1', 0, 0)."""
        traj = cls(model, backend, fallback)
        traj._arrays = (kinds, events, segment_modes, segments)
        return traj

    def _segment(self, k: int) -> tuple[str, Segment]:
        """Segment k, made from the arrays on first use."""
        if self._arrays is None:
            return self._segments[k]
        made = self._made.get(k)
        if made is None:
            name = MODE_NAMES[int(self._arrays[2][k])]
            row = self._arrays[3][k]
            y0 = row[1 : 1 + (4 if name == FREE else 2)].copy()
            made = self._made[k] = (name, Segment(self.model.mode(name), float(row[0]), y0))
        return made

    def _make(self) -> None:
        """Every event and segment of a compiled run as objects (once)."""
        if self._arrays is None:
            return
        kinds, events, modes, _ = self._arrays
        self._segments = [self._segment(k) for k in range(len(modes))]
        self._events = [
            Event(float(r[0]), EVENT_KINDS[k], float(r[1]), float(r[2]), r[3:7].copy(), r[7:11].copy(), float(r[11]))
            for k, r in zip(kinds.tolist(), events)
        ]
        self._arrays, self._made = None, {}

    @property
    def segments(self) -> list[tuple[str, Segment]]:
        """(mode name, :class:`~impactdamper.core.events.Segment`) per segment, in time order."""
        self._make()
        return self._segments

    @property
    def events(self) -> list[Event]:
        """The :class:`Event` objects, in time order."""
        self._make()
        return self._events

    def segment_index(self, t: np.ndarray) -> np.ndarray:
        """Index into :attr:`segments` of the segment that holds each time of ``t`` (the last
        one whose start is at or before it; times before the start map to segment 0)."""
        if self._arrays is not None:
            starts = self._arrays[3][:, 0]
        else:
            starts = np.array([seg.t0 for _, seg in self._segments])
        return np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(starts) - 1)

    def sample(self, t: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """Full states (x1, x2, x1', x2') at times t, shape t.shape + (4,), and the mode
        names (``"free"``/``"stuck"``), shape t.shape. Times must not precede the start."""
        t = np.asarray(t, dtype=float)
        flat = t.reshape(-1)
        start = self._segment(0)[1].t0
        if flat.size and flat.min() < start - 1e-12 * max(abs(start), 1.0):
            raise ValueError(f"`t` = {flat.min()!r} precedes the trajectory's start {start!r}")
        idx = self.segment_index(flat)
        out = np.empty((flat.size, 4))
        modes = np.empty(flat.size, dtype=object)
        for k in np.unique(idx):
            sel = idx == k
            name, seg = self._segment(int(k))
            out[sel] = self.model.full_state(name, seg.state(flat[sel]))
            modes[sel] = name
        return out.reshape(t.shape + (4,)), modes.reshape(t.shape)

    def impacts(self, t_from: float = -math.inf, t_to: float = math.inf) -> list[Event]:
        return [e for e in self.events if e.kind == "impact" and t_from <= e.t < t_to]


def rescale_trajectory(traj: Trajectory, scales: ScaleMap) -> Trajectory:
    """The same motion in ``scales.target``'s units (a new Trajectory; segments and events
    converted by :class:`ScaleMap`)."""
    model = model_of(scales.target)
    out = Trajectory(model)
    for name, seg in traj.segments:
        y = scales.full(seg.y0) if name == FREE else scales.stuck(seg.y0)
        out.segments.append((name, Segment(model.mode(name), scales.apply(seg.t0, "time"), y)))
    for e in traj.events:
        out.events.append(
            Event(
                scales.apply(e.t, "time"),
                e.kind,
                scales.apply(e.velocity, "velocity"),
                scales.apply(e.impulse, "impulse"),
                scales.full(e.before),
                scales.full(e.after),
                scales.apply(e.t_accumulation, "time"),
            )
        )
    return out
