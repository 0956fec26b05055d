"""The many-point call (impactdamper.steady_states): its input refused or read as given, and
its parallel workers giving the serial call's result bit for bit."""

import dataclasses
import math

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.analysis.batch import BatchResult
from impactdamper.analysis.point import SweepSettings

REF = idp.Parameters()
SETTINGS = SweepSettings(max_periods=150, max_periods_after_nonperiodic=50)


# --- input: refused with the point and the name, never reshaped -------------------------------
@pytest.mark.parametrize(
    "names, values, match",
    [
        # (2, P) for two names: refused, not read row by row into other points
        (("gap", "theta"), [[-5.8, -5.0, -4.0], [1.0, 1.1, 1.2]], r"^`values` of shape \(2, 3\) is not allowed"),
        (("gap",), [[[-5.8]]], r"^`values` of shape \(1, 1, 1\) is not allowed"),  # 3-d
        (("gap",), [-5.8, -5.0], r"^`values` of shape \(2,\) is not allowed"),  # 1-d
        (("gap", "gap"), [[-5.8, -5.0]], r"^`names` = .* 'gap' and 'gap' both set gap"),
        (("delta", "delta1"), [[0.1, 0.2]], r"^`names` = .* 'delta' and 'delta1' both set delta1"),
        (("gap", "theta"), [[-5.8, 1.0], [-5.0, 1 + 2j]], r"^`values` point 1, `theta` = \(1\+2j\) is not allowed"),
        (("gap",), [[-5.8], ["-5.0"]], r"^`values` point 1, `gap` = '-5.0' is not allowed"),
        (("gap", "R"), [[-5.8, True]], r"^`values` point 0, `R` = True is not allowed"),
        (("gap",), np.array([[True]]), r"^`values` point 0, `gap` = .*True is not allowed"),
        (("gap", "theta"), [[-5.8, 1.0], [-5.0, math.nan]], r"^`values` point 1, `theta` = nan is not allowed"),
        (("gap", "theta"), [[-5.8, 1.0], [-5.0, -1.0]], r"^`values` point 1 \(theta\): `theta` = -1.0 is not allowed"),
        (("nope",), [[1.0]], r"^`names`"),
        ("gap", [[1.0]], r"^`names`"),
        ((), np.zeros((1, 0)), r"^`names`"),
    ],
)
def test_bad_values_are_refused_by_point_and_name(names, values, match):
    with pytest.raises(ValueError, match=match):
        idp.steady_states(REF, names, values)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(chain_length=0), r"^`chain_length` = 0 is not allowed: must be an integer >= 1"),
        (dict(chain_length=2), r"^`chain_length` = 2 is not allowed: the 3 points must form whole chains"),
        (dict(chain_length=True), r"^`chain_length` = True"),
        (dict(chain=False, chain_length=1), r"^`chain_length` is not allowed with `chain=False`"),
        (dict(workers=0), r"^`workers` = 0 is not allowed: must be an integer >= 1"),
        (dict(workers=2.0), r"^`workers` = 2.0 is not allowed"),
        (dict(workers="2"), r"^`workers` = '2' is not allowed"),
    ],
)
def test_bad_chains_and_workers_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        idp.steady_states(REF, ("gap",), [[-6.0], [-5.8], [-5.0]], **kwargs)


def test_integer_values_are_numbers():
    a = idp.steady_states(REF, ("gap",), [[-6], [2]], settings=SETTINGS)
    b = idp.steady_states(REF, ("gap",), np.array([[-6.0], [2.0]]), settings=SETTINGS)
    assert a.label.tolist() == b.label.tolist() and np.array_equal(a.x1_max, b.x1_max)


# --- chains and workers -------------------------------------------------------------------------
def _same_result(a: BatchResult, b: BatchResult) -> None:
    """Every per-point array equal, bit for bit (NaN where NaN), and the same order."""
    for f in dataclasses.fields(BatchResult):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "elapsed":
            continue
        if isinstance(x, np.ndarray) and x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), f.name
        elif isinstance(x, np.ndarray):
            assert np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


def test_chains_are_independent():
    """Each chain of ``chain_length`` points settles as a call of its own: its first point from
    Algorithm No. 2's step 1, the others from their neighbours."""
    up, down = np.array([-7.0, -6.0, -5.0]), np.array([-5.0, -6.0, -7.0])
    both = idp.steady_states(REF, ("gap",), np.r_[up, down][:, None], settings=SETTINGS, chain_length=3)
    alone = [idp.steady_states(REF, ("gap",), v[:, None], settings=SETTINGS) for v in (up, down)]
    for name in ("regime_code", "period_multiple", "x1_max", "sections", "start_states", "periods"):
        assert np.array_equal(getattr(both, name), np.concatenate([getattr(r, name) for r in alone])), name


@pytest.mark.parametrize("backend", ["compiled", "python"])
def test_a_chain_starts_from_its_given_state(backend):
    """With ``states`` a chain's first point starts from its row (one per chain), the others from
    their neighbours: the first point is the independent point from that state, the second the
    independent point from the first's settled section."""
    start = idp.steady_states(REF, ("gap",), [[-6.0]], settings=SETTINGS).sections[0]
    chained = idp.steady_states(
        REF,
        ("gap",),
        [[-6.0], [-5.8], [-6.0], [-5.8]],
        settings=SETTINGS,
        chain_length=2,
        states=[start, start],
        backend=backend,
    )
    first = idp.steady_states(REF, ("gap",), [[-6.0]], settings=SETTINGS, chain=False, states=[start], backend=backend)
    assert np.array_equal(chained.start_states[0], start) and chained.x1_max[0] == first.x1_max[0]
    assert np.array_equal(chained.start_states[2], start) and chained.x1_max[2] == chained.x1_max[0]
    second = idp.steady_states(
        REF, ("gap",), [[-5.8]], settings=SETTINGS, chain=False, states=[chained.sections[0]], backend=backend
    )
    assert chained.x1_max[1] == pytest.approx(second.x1_max[0], rel=1e-12)
    with pytest.raises(ValueError, match=r"^`states` of shape \(4, 4\) is not allowed: .* one start .* per chain"):
        idp.steady_states(REF, ("gap",), [[-6.0]] * 4, chain_length=2, states=[start] * 4)


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["compiled", "python"])
def test_workers_give_the_serial_result_bit_for_bit(backend):
    """Two processes on blocks of whole chains (and of single points) give the serial call's
    arrays exactly, in the same order: a theta sweep up and down for each of three designs."""
    thetas = np.linspace(0.8, 1.3, 6 if backend == "compiled" else 3)
    designs = [(-5.8, 0.5), (-2.0, 0.7), (-9.0, 0.4)]
    rows = [
        (gap, N, t)
        for gap, N in designs
        for sweep in (thetas, thetas[::-1])  # up, then down: two chains per design
        for t in sweep
    ]
    names, values = ("gap", "N", "theta"), np.array(rows)
    serial = idp.steady_states(REF, names, values, settings=SETTINGS, chain_length=len(thetas), backend=backend)
    parallel = idp.steady_states(
        REF, names, values, settings=SETTINGS, chain_length=len(thetas), workers=2, backend=backend
    )
    _same_result(serial, parallel)
    grid = idp.steady_states(REF, names, values, settings=SETTINGS, chain=False, backend=backend)
    _same_result(
        grid, idp.steady_states(REF, names, values, settings=SETTINGS, chain=False, workers=3, backend=backend)
    )


@pytest.mark.parametrize("backend", ["compiled", "python"])
def test_a_sweep_has_the_same_labels_at_every_free_scale(backend):
    """Points outside the native scales went to the reference one by one without the Newton
    rescue (both backends), and in a chain each np put the next point under the short cap: at
    omega 1e-11 the gaps -12, -9.6, -5.8 read np, np, np against np, 3/2, 1/1 at omega 10. The
    relative problem does not depend on x_st, m1, omega: the same labels, the same x1_max to
    1e-9 relative (the round-off of the units' conversion, far below settle_tol 1e-10's 1e-9 x_st
    accuracy of x1_max) and sections in the point's own units."""
    gaps = np.linspace(-14.0, -2.0, 13)[:, None]
    ref = idp.steady_states(REF, ("gap",), gaps, backend=backend)
    assert {"3/2", "1/1", "np"} <= set(idp.steady_states(REF, ("gap",), [[-12.0], [-9.6], [-5.8]]).label)
    for scales in (dict(omega=1e-11), dict(omega=1e11), dict(x_st=1e31), dict(m1=1e-31)):
        p = REF.replace(**scales)
        res = idp.steady_states(p, ("gap",), gaps, backend=backend)
        assert list(res.label) == list(ref.label), scales
        assert "scales" not in res.fallbacks
        settled = res.regime != "nonperiodic"
        assert np.allclose(res.x1_max[settled], ref.x1_max[settled], rtol=1e-9, atol=0), scales
        relative = res.sections[settled] / [p.x_st, p.x_st, p.x_st * p.omega, p.x_st * p.omega]
        assert np.allclose(relative, ref.sections[settled] / [1.0, 1.0, 10.0, 10.0], rtol=1e-6, atol=1e-6), scales


@pytest.mark.parametrize(
    "names, values, match",
    [
        # A set maps the columns in hash order (theta and N swapped under PYTHONHASHSEED=1).
        ({"theta", "N"}, [[0.9, 0.6]], r"^`names` = .* must be an ordered sequence .* not a set$"),
        (frozenset({"gap"}), [[-5.8]], r"^`names` = .* not a frozenset$"),
        # A generator was read by the check and reported as an empty ().
        ((n for n in ("theta",)), [[0.9]], r"^`names` = <generator .* not a generator$"),
        ({"theta": 0}, [[0.9]], r"^`names` = .* not a dict$"),
        # A masked array's mask was dropped silently.
        (("gap",), np.ma.masked_array([[-5.8], [-5.0]], mask=[[0], [1]]), r"^`values` = an array of shape \(2, 1\)"),
    ],
)
def test_unordered_names_and_masked_values_are_refused_in_one_line(names, values, match):
    with pytest.raises(ValueError, match=match) as info:
        idp.steady_states(REF, names, values)
    assert "\n" not in str(info.value)


def test_a_bad_array_is_summarised_by_shape_and_dtype_in_one_line():
    states = np.ma.masked_array(np.zeros((1, 4)), mask=[[0, 0, 1, 0]])
    with pytest.raises(ValueError, match=r"^`states` = an array of shape \(1, 4\) and dtype float64 \(masked\)"):
        idp.steady_states(REF, ("gap",), [[-5.8]], states=states)
    with pytest.raises(ValueError) as info:
        idp.steady_states(REF, np.array([["gap", "theta"], ["N", "R"]]), [[-5.8]])
    assert "\n" not in str(info.value) and "an array of shape (2, 2)" in str(info.value)


def test_a_period_multiple_no_cap_can_hold_names_itself():
    with pytest.raises(ValueError, match=r"^`max_period_multiple` = 1000000 is not allowed: must be below 50000"):
        SweepSettings(max_period_multiple=10**6)
