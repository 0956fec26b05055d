"""The compiled backend: the kernels behind the registry's ``"compiled"``
(:mod:`impactdamper.core.backends`).

Its operations take arguments the caller validated (:mod:`impactdamper.core.validation`), pack
the parameters (:mod:`~impactdamper.core.compiled.pack`), run one kernel and return the
reference's types. Where the kernels do not apply (a pack flag: repeated roots, free scales
outside the native range, a matrix the reference refuses) or stop on an error that is not a
work bound, the reference runs instead and the result says why (``fallback``). A run that
reaches a work bound (the step budget, more than ``MAX_EVENTS_AT_ONE_TIME`` events at one
instant) raises the reference's :class:`~impactdamper.core.events.SearchLimitError`, worded from
the kernels' diagnostics as the reference words it, without running the reference to its bound.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactdamper.core.backends import PYTHON, Backend, row_arrays
from impactdamper.core.compiled.layout import (
    DIAG_ERR,
    DIAG_IMPACTS,
    DIAG_START,
    DIAG_TIME,
    DIAG_USED,
    ERR_DEGENERATE,
    FALLBACK_REASONS,
    MODE_FREE,
    N_DIAG,
    WORK_BOUND_ERRORS,
)
from impactdamper.core.compiled.loop import pack_simulate_kernel, simulate_kernel
from impactdamper.core.compiled.pack import (
    PACKING_ERRORS,
    PARAMETER_COLUMNS,
    pack_many,
    pack_parameters,
    packing_values,
)
from impactdamper.core.compiled.settle import ROW_DONE, ROW_ERROR, ROW_FLAGGED, ROW_RESCUE, row_kernel, steady_kernel
from impactdamper.core.compiled.tangent import C_CAPTURES, C_GRAZING, C_IMPACTS, C_LIFTOFFS, tangent_kernel
from impactdamper.core.events import SearchLimitError, Segment
from impactdamper.core.model import FREE, STUCK, model_of
from impactdamper.core.parameters import Parameters
from impactdamper.core.settled_cycle import REGIMES, CycleImpact, SteadyState, describe_run
from impactdamper.core.simulate import budget_exceeded, default_initial_state, degenerate_contact
from impactdamper.core.steady import start_in_first_period
from impactdamper.core.tangent import TangentRun
from impactdamper.core.trajectory import Trajectory
from impactdamper.core.validation import SettleOptions, Tolerances, work_bound_message

__all__ = ["CompiledBackend", "COMPILED"]

# Events per forcing period a run's buffers are first sized for (a periodic impacting motion has
# 1-3; a chatter cycle ~30, found by growing them).
EVENTS_PER_PERIOD_GUESS = 4
# A run's buffers hold at least this many events at first.
MIN_CAPACITY = 256
# A settled point's regime code at or above this is not periodic (REGIMES' order).
NONPERIODIC = REGIMES.index("nonperiodic")


def _fill_settled(out, ints: np.ndarray, floats: np.ndarray, settled: slice) -> None:
    """Copy the points ``settled`` from the row kernel's integer and float columns into
    ``out``'s arrays (:class:`~impactdamper.core.backends.RowArrays`)."""
    for j, name in enumerate(("regime_code", "period_multiple", "impacts_per_cycle", "periods", "section_modes")):
        getattr(out, name)[settled] = ints[settled, j]
    for j, name in enumerate(("x1_max", "contact_fraction", "residual")):
        getattr(out, name)[settled] = floats[settled, j]


def _left_to_caller(code: int, stop: int, rows: np.ndarray, flags, tolerances: Tolerances, diag, tail: np.ndarray):
    """What :meth:`CompiledBackend.settle_row` yields for the point ``stop`` where the row kernel
    stopped with ``code``: (index, reason, its payload), the reason ``"rescue"`` (the run's last
    sections), a pack flag's, ``"failed"`` (a work bound, with the reference's line) or
    ``"error"``."""
    if code == ROW_RESCUE:
        return stop, "rescue", tail.copy()
    if code == ROW_FLAGGED:
        return stop, FALLBACK_REASONS[int(flags[stop])], None
    if code == ROW_ERROR and int(diag[DIAG_ERR]) in WORK_BOUND_ERRORS:
        p = Parameters(**{c: float(x) for c, x in zip(PARAMETER_COLUMNS, rows[stop])})
        return stop, "failed", _work_bound(p, tolerances, diag)
    return stop, "error", None


def _work_bound(p: Parameters, tolerances: Tolerances, diag: np.ndarray) -> str:
    """The reference's line for a run that reached a work bound, from the kernels' diagnostics."""
    if int(diag[DIAG_ERR]) == ERR_DEGENERATE:
        what = degenerate_contact(float(diag[DIAG_TIME]))
    else:
        what = budget_exceeded(diag[DIAG_USED], (diag[DIAG_TIME] - diag[DIAG_START]) / p.T)
    return work_bound_message(p, tolerances, what, int(diag[DIAG_IMPACTS]))


def _by_reference(p: Parameters, tolerances: Tolerances, flag: int, err: int, diag: np.ndarray, reference):
    """Where the kernels did not apply (a pack flag) or stopped (``err``): a work bound raises
    the reference's error worded from the kernels' diagnostics; else the reference runs
    (``reference()``: its result, or its own error) and its result says why (``fallback``)."""
    if not flag and err in WORK_BOUND_ERRORS:
        raise SearchLimitError(_work_bound(p, tolerances, diag))
    result = reference()
    reason = FALLBACK_REASONS[flag] if flag else "error"
    if isinstance(result, SteadyState):  # (frozen)
        return dataclasses.replace(result, fallback=reason)
    result.fallback = reason
    return result


class CompiledBackend(Backend):
    """Algorithm No. 2 and the settled motion in the numba kernels (see the module docstring)."""

    name = "compiled"

    def run(self, p: Parameters, t_end: float, t0: float, state, tolerances: Tolerances) -> Trajectory:
        """:func:`impactdamper.core.simulate.simulate`'s motion: a Trajectory holding the
        kernels' arrays, its Event and Segment objects made when first read."""
        v, tols, flag = packing_values(p, tolerances)
        full = default_initial_state(p) if state is None else state
        capacity = max(MIN_CAPACITY, int(EVENTS_PER_PERIOD_GUESS * (t_end - t0) / p.T))
        diag, err = np.zeros(N_DIAG), 0
        if not flag:
            try:
                flag, err, ev_k, ev_f, seg_m, seg_f = pack_simulate_kernel(v, tols, t0, full, t_end, capacity, diag)
            except PACKING_ERRORS:
                flag = FALLBACK_REASONS.index("error")
        if flag or err:
            return _by_reference(p, tolerances, flag, err, diag, lambda: PYTHON.run(p, t_end, t0, state, tolerances))
        return Trajectory.from_arrays(model_of(p), ev_k, ev_f, seg_m, seg_f)

    def settle(self, p: Parameters, t0: float, state, tolerances: Tolerances, options: SettleOptions) -> SteadyState:
        """:func:`impactdamper.core.steady.steady_state`'s result: the period loop and the
        cycle's description (impacts, regime, contact fraction, x1_max by golden-section search
        where the reference uses Brent's, both to 1e-12 T) in the kernels, with the describing
        run's trajectory; a cycle with persistent contact (or every cycle, with
        ``options.describe`` ``"reference"``) is described by the reference's
        :func:`~impactdamper.core.settled_cycle.describe_run` on that trajectory."""
        pack = pack_parameters(p, tolerances)
        diag = np.zeros(N_DIAG)

        def reference():
            return PYTHON.settle(p, t0, state, tolerances, options)

        if pack.fallback:
            return _by_reference(p, tolerances, pack.fallback, 0, diag, reference)
        start = start_in_first_period(p, t0)
        full = default_initial_state(p) if state is None else state
        (err, regime, k, cycle_start, frac, x1_max, n, residual, states, imp, _, ev_k, ev_f, seg_m, seg_f) = (
            steady_kernel(
                pack.cm,
                pack.fm,
                pack.fc,
                pack.fk,
                pack.fg,
                pack.s,
                start,
                full,
                state is None,
                options.settle_tol,
                options.max_periods,
                options.max_period_multiple,
                diag,
            )
        )
        if err:
            return _by_reference(p, tolerances, 0, err, diag, reference)
        trajectory = Trajectory.from_arrays(model_of(p), ev_k, ev_f, seg_m, seg_f)
        if frac > 0.0 or options.describe == "reference":  # (contact phases: as the reference does)
            s = describe_run(p, start, states, int(k), float(residual), full, tolerances, trajectory=trajectory)
            return dataclasses.replace(s, backend="compiled")
        return SteadyState(
            p=p,
            regime=REGIMES[regime],
            period_multiple=int(k),
            impacts=tuple(CycleImpact(*map(float, row)) for row in imp),
            cycle_start=float(cycle_start),
            contact_fraction=float(frac),
            contact_phases=(),
            x1_max=float(x1_max),
            periods=int(n),
            residual=float(residual),
            trajectory=trajectory,
            section_times=start + p.T * np.arange(1, n + 1),
            sections=np.array(states, float),
            backend="compiled",
        )

    def map_step(self, p: Parameters, tolerances: Tolerances):
        """The stroboscopic map by the kernels (the parameters packed once: a Newton iteration
        evaluates the map many times at one set): ``step(state, k)`` -> the state and mode at
        t = k T from ``state`` at t = 0, or None where the kernels do not apply or stopped
        (the caller then runs the reference, which raises its own error where there is one)."""
        pack = pack_parameters(p, tolerances)
        if pack.fallback:
            return None
        model = model_of(p)
        diag = np.zeros(N_DIAG)

        def step(state, k):
            t_end = k * p.T
            capacity = max(MIN_CAPACITY, EVENTS_PER_PERIOD_GUESS * k)
            args = (pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s)
            err, _, _, seg_m, seg_f = simulate_kernel(*args, 0.0, np.asarray(state, float), t_end, capacity, diag)
            if err:
                return None
            name = FREE if seg_m[-1] == MODE_FREE else STUCK
            row = seg_f[-1]
            seg = Segment(model.mode(name), float(row[0]), row[1 : 1 + (4 if name == FREE else 2)].copy())
            return model.full_state(name, seg.state(np.array([t_end])))[0], name

        return step

    def settle_row(
        self,
        rows: np.ndarray,
        out,
        *,
        tolerances: Tolerances,
        options: SettleOptions,
        max_periods_after_nonperiodic: int,
        chain_length: int,
        rescue: bool,
        given: np.ndarray,
        tail_rows: int,
    ):
        """Settle the points ``rows`` in order in the kernels (:func:`row_kernel`), as the
        reference's ladder without accelerators, into ``out``'s arrays (``regime_code``,
        ``period_multiple``, ``impacts_per_cycle``, ``periods``, ``section_modes``, ``x1_max``,
        ``contact_fraction``, ``residual``, ``start_states``, ``sections``, ``phases``,
        ``velocities``) with ``options``' period test and cap. Point i continues point i - 1
        unless ``chain_length`` is 0 or divides i; else it starts from ``given[i]`` (shape
        (P, 4); (0, 4): none) or Algorithm No. 2's step 1. ``max_periods_after_nonperiodic`` caps a point whose predecessor did not settle.
        Yields the points the kernels leave to the caller (:class:`~impactdamper.core.backends.Backend`):
        a pack flag or an error (its reason), a work bound (``"failed"``, with the reference's
        line), a nonperiodic point with ``rescue`` (``"rescue"``, with the run's last
        ``tail_rows`` section states, oldest first, rows before the run NaN)."""
        pack, flags = pack_many(rows, tolerances)
        P = len(rows)
        ints = np.zeros((P, 5), np.int64)  # regime code, k, z, periods, section mode
        floats = np.full((P, 3), np.nan)  # x1_max, contact fraction, residual
        tail = np.full((tail_rows, 4), np.nan)
        diag = np.zeros(N_DIAG)
        prev = np.zeros(7)  # (have one, section (4), its mode, periodic)
        i = 0
        while i < P:
            code, stop = row_kernel(
                pack.s,
                pack.cm,
                pack.fm,
                pack.fc,
                pack.fk,
                pack.fg,
                flags,
                i,
                prev,
                chain_length,
                rescue,
                options.settle_tol,
                options.max_periods,
                max_periods_after_nonperiodic,
                options.max_period_multiple,
                given,
                ints,
                floats,
                out.start_states,
                out.sections,
                out.phases,
                out.velocities,
                tail,
                diag,
            )
            _fill_settled(out, ints, floats, slice(i, stop + 1 if code == ROW_RESCUE else stop))
            if code == ROW_DONE:
                return
            yield _left_to_caller(code, stop, rows, flags, tolerances, diag, tail)
            # Point `stop` as the caller filled it is the next point's predecessor.
            prev[0], prev[1:5], prev[5] = 1.0, out.sections[stop], out.section_modes[stop]
            prev[6] = 1.0 if out.regime_code[stop] < NONPERIODIC else 0.0
            i = stop + 1

    def lyapunov(
        self, p: Parameters, t0: float, state, tolerances: Tolerances, periods: int, transient: int, warmup: int
    ) -> TangentRun:
        """The reference's :func:`~impactdamper.core.tangent.tangent_walk` in the kernels
        (:func:`~impactdamper.core.compiled.tangent.tangent_kernel`, on the kernels' own event
        loop and its work bound); where they do not apply, or stop on an error other than the
        work bound, the reference walks (``fallback``)."""
        pack = pack_parameters(p, tolerances)
        err, diag = 0, np.zeros(N_DIAG)
        if not pack.fallback:
            full = default_initial_state(p) if state is None else np.asarray(state, float)
            increments, sections = np.empty((periods, 4)), np.empty((periods, 4))
            counts = np.zeros(4, np.int64)
            args = (pack.cm, pack.fm, pack.fc, pack.fk, pack.fg, pack.s)
            err, dimension, contact = tangent_kernel(
                *args, t0, full.copy(), transient, warmup, periods, increments, sections, counts, diag
            )
            if not err:
                return TangentRun(
                    increments=increments,
                    sections=sections,
                    dimension=int(dimension),
                    impacts=int(counts[C_IMPACTS]),
                    captures=int(counts[C_CAPTURES]),
                    liftoffs=int(counts[C_LIFTOFFS]),
                    grazing=int(counts[C_GRAZING]),
                    contact_time=float(contact),
                    backend="compiled",
                )
        return _by_reference(
            p,
            tolerances,
            pack.fallback,
            err,
            diag,
            lambda: PYTHON.lyapunov(p, t0, state, tolerances, periods, transient, warmup),
        )

    def warm_up(self) -> None:
        """Every kernel run once on the reference case (compiled, or loaded from numba's cache)."""
        p, tol = Parameters(), Tolerances()
        self.lyapunov(p, 0.0, None, tol, 2, 1, 1)
        self.settle(p, 0.0, None, tol, SettleOptions(max_periods=40))
        self.settle(Parameters(theta=0.8), 0.0, None, tol, SettleOptions(max_periods=40))  # (a contact cycle)
        self.run(p, 2 * p.T, 0.0, None, tol)
        self.map_step(p, tol)(default_initial_state(p), 1)

        rows = np.array([[getattr(p, c) for c in PARAMETER_COLUMNS]] * 2)
        out = row_arrays(2, 4)
        options = SettleOptions(settle_tol=1e-9, max_periods=40)
        given = np.zeros((0, 4))
        for _ in self.settle_row(
            rows,
            out,
            tolerances=tol,
            options=options,
            max_periods_after_nonperiodic=40,
            chain_length=2,
            rescue=True,
            given=given,
            tail_rows=17,
        ):
            pass


COMPILED = CompiledBackend()
