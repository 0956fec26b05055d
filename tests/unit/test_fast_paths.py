"""The pure-Python solver's hot paths give the general code's numbers to the bit.

The reference solver (core/simulate.py, core/events.py) takes shortcuts on its hot path: a
segment's state at one time from its own modal coefficients, the event search's modal sums
unrolled for the free mode's two pairs of roots, and a model built once per parameter set.
Each shortcut must leave every number as it was (the workflow's record is compared byte for
byte), so each is held here to the general code, bit for bit."""

import cmath

import numpy as np
import pytest

from helpers import REF

from impactdamper.core.events import Segment
from impactdamper.core.model import Model, model_of


# Parameter ranges of the random cases: wide, damping down to none, gaps from deep contact to none.
RANGES = {"theta": (0.3, 3.0), "mu": (0.01, 0.5), "N": (0.2, 2.0), "delta1": (0.0, 0.3), "delta2": (0.0, 0.3)}
RANGES |= {"gap": (-30.0, 10.0)}


def _random_parameters(rng, count):
    for _ in range(count):
        yield REF.replace(**{name: float(rng.uniform(*bounds)) for name, bounds in RANGES.items()})


def test_a_segments_state_at_one_time_is_the_modes_state_to_the_bit():
    rng = np.random.default_rng(20261127)
    compared = 0
    for p in _random_parameters(rng, 60):
        model = Model(p)
        for mode in (model.free, model.stuck):
            y0 = rng.normal(size=mode.n) * rng.uniform(0.01, 10.0)
            seg = Segment(mode, float(rng.uniform(0.0, 500.0)), y0)
            for t in seg.t0 + rng.uniform(0.0, 20.0, 25):
                fast, general = seg.state(float(t)), mode.state(float(t), seg.t0, seg.y0)
                assert fast.tobytes() == general.tobytes(), (p, mode.n, t, fast - general)
                compared += 1
    assert compared == 60 * 2 * 25


def _loop_evaluator(seg, fn):
    """The event search's modal sums as the general loop writes them."""
    beta = (fn.cV * seg._alpha).tolist()
    terms = [(2.0 * beta[j] if pair else beta[j], lam) for j, lam, pair in seg.mode.pair_roots]
    w, G, g0, t0 = seg.mode.omega, fn.G, fn.g0, seg.t0

    def evaluate(t):
        tau = t - t0
        s0 = s1 = 0j
        for b, lam in terms:
            e = b * cmath.exp(lam * tau)
            s0 += e
            s1 += lam * e
        rot = cmath.exp(1j * w * t) * G
        return g0 + rot.imag + s0.real, w * rot.real + s1.real

    return evaluate, len(terms)


def test_the_free_modes_unrolled_modal_sums_are_the_loops_to_the_bit():
    rng = np.random.default_rng(7)
    compared = 0
    for p in _random_parameters(rng, 40):
        model = Model(p)
        seg = Segment(model.free, float(rng.uniform(0.0, 500.0)), rng.normal(size=4))
        reference, terms = _loop_evaluator(seg, model.gap)
        assert terms == 2  # (two complex pairs: the unrolled path is the one under test)
        unrolled = seg.evaluator(model.gap)
        for t in seg.t0 + rng.uniform(0.0, 5.0, 25):
            assert unrolled(float(t)) == reference(float(t))
            compared += 1
    assert compared == 40 * 25


def test_one_model_per_parameter_set_and_a_refused_set_refused_every_time():
    assert model_of(REF) is model_of(REF.replace())
    assert model_of(REF) is not model_of(REF.replace(gap=-4.0))
    # (the free suppressor's undamped natural frequency, as the command-line test forces it)
    resonant = REF.replace(theta=1.0131335798012997, delta1=0.0, delta2=0.0)
    for _ in range(2):
        with pytest.raises(ValueError, match="`theta`"):
            model_of(resonant)
