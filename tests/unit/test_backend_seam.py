"""The backend seam: each call's arguments checked once on both backends, and a new backend
that writes only ``run`` and ``settle`` (the other operations the :class:`Backend` defaults,
the reference's) passed as an object behind every front door."""

import sys
from collections import Counter

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.analysis.point import SweepSettings
from impactdamper.core import validation
from impactdamper.core.backends import PYTHON, Backend, check_backend, get_backend
from impactdamper.core.validation import Tolerances

P = idp.Parameters()
GAPS = [[-9.6], [-9.0], [-8.0]]


class Delegating(Backend):
    """A new backend in its least form: ``run`` and ``settle``, each the reference's, counted."""

    name = "delegating"

    def __init__(self):
        self.calls = Counter()

    def run(self, p, t_end, t0, state, tolerances):
        self.calls["run"] += 1
        return PYTHON.run(p, t_end, t0, state, tolerances)

    def settle(self, p, t0, state, tolerances, options):
        self.calls["settle"] += 1
        return PYTHON.settle(p, t0, state, tolerances, options)


@pytest.fixture
def checks(monkeypatch):
    """How often each whole-call check runs, counted wherever the library imported it."""
    counts = Counter()
    for name in ("check_settle_call", "check_run_call"):
        original = getattr(validation, name)

        def counted(*args, _name=name, _original=original, **kwargs):
            counts[_name] += 1
            return _original(*args, **kwargs)

        for module in list(sys.modules.values()):
            if module.__name__.startswith("impactdamper") and getattr(module, name, None) is original:
                monkeypatch.setattr(module, name, counted)
    return counts


# Each front door's whole-call checks: once (steady_states checks its input in batch_input, once,
# and no point is checked again).
CALLS = {
    "simulate": (lambda b: idp.simulate(P, 3 * P.T, backend=b), {"check_run_call": 1}),
    "steady_state": (lambda b: idp.steady_state(P, backend=b), {"check_settle_call": 1}),
    "steady_states": (lambda b: idp.steady_states(P, ("gap",), GAPS[1:], backend=b), {}),
}


@pytest.mark.parametrize("backend", ["python", "compiled"])
@pytest.mark.parametrize("call", sorted(CALLS))
def test_each_call_is_checked_once(checks, call, backend):
    run, expected = CALLS[call]
    run(backend)
    assert dict(checks) == expected


def test_a_backend_must_write_run_and_settle():
    class RunOnly(Backend):
        def run(self, p, t_end, t0, state, tolerances): ...

    with pytest.raises(TypeError, match="settle"):
        RunOnly()


def test_a_backend_object_is_accepted_where_a_name_is():
    b = Delegating()
    assert check_backend(b) is b and get_backend(b) == (b, "")
    assert SweepSettings(backend=b).backend is b


def test_new_backend_simulates():
    b = Delegating()
    new, ref = idp.simulate(P, 5 * P.T, backend=b), idp.simulate(P, 5 * P.T, backend="python")
    assert b.calls == {"run": 1}
    assert [(e.t, e.kind) for e in new.events] == [(e.t, e.kind) for e in ref.events]


def test_new_backend_settles_one_point():
    b = Delegating()
    new, ref = idp.steady_state(P, backend=b), idp.steady_state(P, backend="python")
    assert b.calls == {"settle": 1}
    assert (new.regime, new.period_multiple, new.impacts, new.x1_max) == (
        ref.regime,
        ref.period_multiple,
        ref.impacts,
        ref.x1_max,
    )


def test_new_backend_settles_many_points_by_its_own_settle():
    """The default row hands every point to the ladder, which settles it by the new backend."""
    b = Delegating()
    new = idp.steady_states(P, ("gap",), GAPS, backend=b)
    ref = idp.steady_states(P, ("gap",), GAPS, backend="python")
    assert b.calls["settle"] >= 1 and new.backend == "delegating"
    for name in ("regime_code", "period_multiple", "impacts_per_cycle", "x1_max", "sections", "phases"):
        np.testing.assert_array_equal(getattr(new, name), getattr(ref, name), err_msg=name)


def test_new_backend_walks_the_tangent_map_and_steps_the_map_by_the_defaults():
    b = Delegating()
    options = dict(periods=20, transient=20, warmup=10, blocks=10)
    new = idp.lyapunov_spectrum(P, **options, backend=b)
    ref = idp.lyapunov_spectrum(P, **options, backend="python")
    np.testing.assert_array_equal(new.exponents, ref.exponents)
    x0, tol = idp.default_initial_state(P), Tolerances()
    (state, mode), (ref_state, ref_mode) = b.map_step(P, tol)(x0, 2), PYTHON.map_step(P, tol)(x0, 2)
    np.testing.assert_array_equal(state, ref_state)
    assert mode == ref_mode


def test_new_backend_seeds_an_orbit():
    b = Delegating()
    new, ref = idp.solve_orbit(P, "simulate", backend=b), idp.solve_orbit(P, "simulate")
    assert b.calls == {"settle": 1}
    np.testing.assert_array_equal(new.multipliers, ref.multipliers)
