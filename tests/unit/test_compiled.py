"""The compiled backend (impactdamper.core.compiled) and the many-point call
(impactdamper.steady_states, impactdamper.analysis.batch) against the pure-Python reference.

Event times: two correct implementations of the same algorithm agree to the rounding of their
arithmetic only as far as the motion's conditioning allows. An impact's time moves by
dg / v when the gap g is off by dg at closing velocity v; along an accumulating sequence
(chatter) the errors of earlier, slower impacts carry into later ones. The tolerance per event
is therefore the brief's 1e-12 T plus CONDITIONING times the rounding of positions
(eps * X, X the largest position) over the slowest closing velocity so far. After a grazing
touch (v below TOUCH_VELOCITY) the map's square-root singularity amplifies any difference
without bound (the hard case "grazing_alg1_onset": 6e-10 T at the touch, 5e-5 T three
periods on), so later times are not compared; kinds and order are, over the whole window.
"""

import dataclasses
import math

import numpy as np
import pytest

import impactdamper as idp
from impactdamper import Parameters
from impactdamper.analysis.adaptive import adaptive_regime_map
from impactdamper.analysis.batch import BATCH_REGIMES, random_starts_batch
from impactdamper.analysis.ladder import solve_point
from impactdamper.analysis.point import SweepSettings
from impactdamper.analysis.rescue import rescue_from_sections
from impactdamper.analysis.sweeps import random_start_states, sweep, two_way_sweep, with_value
from impactdamper.core.backends import get_backend, warm_up
from impactdamper.core.compiled.layout import FALLBACK_REASONS, N_DIAG
from impactdamper.core.compiled.loop import pack_simulate_kernel, simulate_kernel
from impactdamper.core.compiled.pack import pack_parameters, packing_values
from impactdamper.core.simulate import Tolerances, default_initial_state, simulate
from impactdamper.core.steady import steady_state
from impactdamper.core.validation import SettleOptions
from impactdamper.studies.performance.hardcases import TOUCH_VELOCITY, _hard_cases

# Event times agree to this, in forcing periods, where the motion is well conditioned (the brief).
TIME_TOL = 1e-12
# Allowed amplification of the position rounding eps * X over the slowest closing velocity so
# far (measured: at most 2 on the hard cases over 10 periods; 100 leaves room for other
# parameter sets, and stays below 1e-8 T for every compared event).
CONDITIONING = 100.0
# Periods over which the events are compared.
WINDOW_PERIODS = 10
# Settled results: phases in T and x1_max in x_st (both settle to settle_tol = 1e-10; the
# reference's Brent search and the kernels' golden section stop at 1e-12 T).
PHASE_TOL = 1e-9
X1_TOL = 1e-9


@pytest.fixture(scope="module", autouse=True)
def compiled_kernels():
    """Compile (or load the cache of) every kernel once for the module."""
    return warm_up("compiled")


def compare_events(p, t0, state, periods=WINDOW_PERIODS):
    """(largest time difference over its tolerance, events compared); asserts kinds and order."""
    a = idp.simulate(p, t0 + periods * p.T, t0, state, backend="compiled")
    b = simulate(p, t0 + periods * p.T, t0, state)
    assert [e.kind for e in a.events] == [e.kind for e in b.events]
    X = max([1.0] + [float(np.max(np.abs(e.before[:2]))) / p.x_st for e in b.events]) * p.x_st
    v_min, worst, compared = math.inf, 0.0, 0
    for ea, eb in zip(a.events, b.events):
        if eb.kind == "impact":
            v = eb.velocity / (p.x_st * p.omega)
            if v < TOUCH_VELOCITY:
                break
            v_min = min(v_min, eb.velocity)
        tol = TIME_TOL * p.T + CONDITIONING * np.finfo(float).eps * X / v_min
        worst = max(worst, abs(ea.t - eb.t) / tol)
        compared += 1
    return worst, compared, a.backend == "compiled"


# --- closed-form checks on the compiled events ------------------------------------------------
@pytest.mark.parametrize("R", [0.0, 0.7, 1.0])
def test_impact_law(R):
    """Every compiled impact: the relative velocity becomes -R times itself, momentum is kept,
    energy never rises; the gap at the impact is zero (the event residual)."""
    p = Parameters(R=R)
    traj = idp.simulate(p, 10 * p.T, backend="compiled")
    impacts = [e for e in traj.events if e.kind == "impact"]
    assert traj.backend == "compiled" and impacts
    vs = p.x_st * p.omega
    for e in impacts:
        v_before = e.before[3] - e.before[2]
        v_after = e.after[3] - e.after[2]
        assert abs(v_after + R * v_before) <= 1e-12 * vs
        momentum = p.m1 * e.before[2] + p.m2 * e.before[3]
        assert abs(p.m1 * e.after[2] + p.m2 * e.after[3] - momentum) <= 1e-12 * p.m1 * vs
        assert traj.model.energy(e.after) <= traj.model.energy(e.before) * (1 + 1e-14)
        assert abs(traj.model.gap_of(e.before)) <= 1e-12 * p.x_st


@pytest.mark.parametrize("gap", [-5.8, 5.0])
def test_gap_at_impacts_from_the_flow(gap):
    """The gap of the compiled trajectory's segment at each impact, from the exact flow, is
    within the grazing tolerance of zero (both signs of the initial gap)."""
    p = Parameters(gap=gap)
    traj = idp.simulate(p, 10 * p.T, backend="compiled")
    for e in traj.impacts():
        full, _ = traj.sample(np.array([e.t - 1e-15]))
        assert abs(traj.model.gap_of(full[0])) <= 1e-9 * p.x_st


# --- the same events as the reference ----------------------------------------------------------
HARD = {h.name: h for h in _hard_cases()}


@pytest.mark.parametrize("name", sorted(HARD))
def test_hard_case_events(name):
    h = HARD[name]
    p = h.parameters()
    t0, state = h.initial(p)
    worst, compared, used_kernels = compare_events(p, t0, state)
    assert worst <= 1.0, f"{name}: time difference {worst:.3g} x its tolerance over {compared} events"
    # Only the double root of eq. (4) needs the matrix exponential (the reference runs it).
    assert used_kernels == (name != "repeated_roots")


def random_parameters(seed):
    rng = np.random.default_rng(seed)
    return Parameters(
        theta=rng.uniform(0.5, 2.0),
        mu=rng.uniform(0.02, 0.3),
        N=rng.uniform(0.3, 1.5),
        delta1=rng.uniform(0.0, 0.2),
        delta2=rng.uniform(0.0, 0.2),
        R=rng.uniform(0.0, 1.0),
        gap=rng.uniform(-20.0, 10.0),
    )


@pytest.mark.parametrize("seed", range(10))
def test_random_parameter_events(seed):
    p = random_parameters(seed)
    worst, compared, used_kernels = compare_events(p, 0.0, None)
    assert used_kernels
    assert worst <= 1.0, f"{p}: time difference {worst:.3g} x its tolerance over {compared} events"


# --- packing in one compiled call ---------------------------------------------------------
def test_compiled_eig_is_numpys():
    """The packing's dgeev call gives numpy's eig bit for bit: complex pairs (damped), real roots
    (overdamped) and undamped roots, on random free-mode matrices."""
    from impactdamper.core.compiled.modal import real_eig
    from impactdamper.core.compiled.pack import _state_matrices

    rng = np.random.default_rng(3)
    kinds = set()
    for i in range(300):
        p = Parameters(
            theta=rng.uniform(0.2, 4.0),
            mu=rng.uniform(0.01, 2.0),
            N=rng.uniform(0.1, 4.0),
            delta1=rng.uniform(0.0, 3.0) * (i % 3 > 0),
            delta2=rng.uniform(0.0, 3.0) * (i % 5 > 0),
        )
        M = _state_matrices(packing_values(p)[0])[0]
        ok, lam, V = real_eig(M)
        lam_np, V_np = np.linalg.eig(M)
        assert ok
        assert np.array_equal(lam, lam_np) and np.array_equal(V, V_np), p
        kinds.add(int(np.sum(lam_np.imag == 0.0)))
    assert {0, 4} <= kinds  # both all-complex and all-real spectra were drawn


@pytest.mark.parametrize("seed", range(4))
def test_packed_in_the_run_is_packed_apart(seed):
    """A run packing its parameters inside its kernel call (the public simulate's) gives the
    events of a run on a separate pack (the map step's)."""
    p = random_parameters(seed)
    v, tols, _ = packing_values(p)
    full, diag = default_initial_state(p), np.zeros(N_DIAG)
    flag, err, *a = pack_simulate_kernel(v, tols, 0.0, full, 5 * p.T, 256, diag)
    pk = pack_parameters(p)
    err_b, *b = simulate_kernel(pk.cm, pk.fm, pk.fc, pk.fk, pk.fg, pk.s, 0.0, full, 5 * p.T, 256, diag)
    assert (flag, err, err_b) == (0, 0, 0)
    assert all(np.array_equal(x, y) for x, y in zip(a, b))


def test_packed_in_the_run_falls_back_as_the_pack():
    """Where the pack is flagged (a double root, outside the native scales), the fused run
    stops with the pack's flag, and the public call runs the reference and names the reason."""
    delta2 = HARD["repeated_roots"].changes["delta2"]
    for p in (Parameters(N=0.9, delta2=delta2), Parameters(x_st=1e-40)):
        v, tols, flag = packing_values(p)
        if not flag:
            flag = pack_simulate_kernel(v, tols, 0.0, default_initial_state(p), 2 * p.T, 256, np.zeros(N_DIAG))[0]
        assert flag == pack_parameters(p).fallback != 0
        traj = idp.simulate(p, 2 * p.T, backend="compiled")
        assert (traj.backend, traj.fallback) == ("python", FALLBACK_REASONS[flag])
    # A fast rate inside the native range is no repeated root: omega 1e7 (and 1e-8) fell back
    # to the matrix exponential, its eigenvectors tested in (x, v) units; they stay in the kernels.
    for p in (Parameters(omega=1e7), Parameters(omega=1e-8), Parameters(theta=0.01)):
        assert pack_parameters(p).fallback == 0
        traj = idp.simulate(p, 2 * p.T, backend="compiled")
        assert (traj.backend, traj.fallback) == ("compiled", "")


# --- the same settled motions -------------------------------------------------------------
SWEEP_GAPS = np.linspace(-34.0, 14.0, 13)


@pytest.mark.parametrize("gap", SWEEP_GAPS)
def test_steady_state_on_sweep_grid(gap):
    p = Parameters(gap=float(gap))
    a = idp.steady_state(p, max_periods=300, backend="compiled")
    b = steady_state(p, max_periods=300)
    assert a.fallback == ""
    assert (a.regime, a.periods) == (b.regime, b.periods)
    # A nonperiodic run (chaotic at gap -18) amplifies rounding differences without bound: its
    # last window's impacts are not the same motion, only its verdict is.
    if b.settled:
        assert (a.period_multiple, a.impacts_per_cycle) == (b.period_multiple, b.impacts_per_cycle)
        phases = np.array([i.phase for i in b.impacts])
        assert np.all(np.abs(np.array([i.phase for i in a.impacts]) - phases) <= PHASE_TOL)
        assert abs(a.x1_max - b.x1_max) <= X1_TOL


def test_batch_matches_regime_map():
    """A coarse theta map: the batch (the brute-force map) gives the reference's chained sweeps'
    points without their accelerators (regime and periods everywhere; k, z and x1_max to X1_TOL on settled points);
    nonperiodic points get the reference's Newton rescue (from the kernels' last sections) and
    the ones it settles are counted. A nonperiodic (chaotic)
    run's last window is not compared: rounding differences grow without bound there (on the
    CI config's 12 x 12 maps 6 of 288 points differ in that window's z, none in the regime)."""
    base = Parameters()
    gaps, thetas = np.linspace(-40.0, 15.0, 8), np.linspace(0.5, 1.5, 4)
    settings = SweepSettings(settle_tol=1e-9, max_periods=100, max_periods_after_nonperiodic=40, continuation=False)
    m = adaptive_regime_map(base, "gap", gaps, "theta", thetas, settings=settings, brute_force=True)
    python = dataclasses.replace(settings, backend="python")
    ref = [sweep(with_value(base, "theta", float(t)), "gap", gaps, settings=python) for t in thetas]
    for r, row in enumerate(ref):
        assert [BATCH_REGIMES[c] for c in m.regime_code[r]] == [pt.regime for pt in row]
        assert list(m.periods[r]) == [pt.periods for pt in row]
        for i, pt in enumerate(row):
            if pt.regime != "nonperiodic":
                assert (m.period_multiple[r, i], m.impacts_per_cycle[r, i]) == (
                    pt.period_multiple,
                    pt.impacts_per_cycle,
                )
                assert abs(m.x1_max[r, i] - pt.x1_max) <= X1_TOL
        assert list(m.method[r]) == [pt.method for pt in row]
    # The rescue runs from the kernels' last sections; only the points it settles are counted.
    assert set(m.fallbacks) <= {"rescue"}
    assert m.fallbacks.get("rescue", 0) == sum(pt.method == "rescue" for row in ref for pt in row)


def test_batch_down_and_unchained():
    """Direction down gives the cells in increasing order; chain=False starts each point
    from Algorithm No. 2's step 1, as steady_state does."""
    base = Parameters()
    gaps = np.array([-8.0, -5.8, 2.0])
    settings = SweepSettings(settle_tol=1e-9, max_periods=100, max_periods_after_nonperiodic=40, rescue=False)
    down = adaptive_regime_map(base, "gap", gaps, "theta", [1.0], direction="down", settings=settings, brute_force=True)
    assert list(down.fast_values) == sorted(gaps)
    descending = np.column_stack([np.sort(gaps)[::-1], np.ones(len(gaps))])
    chain = idp.steady_states(base, ("gap", "theta"), descending, settings=settings)
    assert list(down.label[0]) == list(chain.label[::-1])
    single = idp.steady_states(base, ("gap",), gaps[:, None], settings=settings, chain=False)
    for i, g in enumerate(gaps):
        s = steady_state(Parameters(gap=float(g)), settle_tol=1e-9, max_periods=100)
        assert (single.regime[i], single.period_multiple[i]) == (s.regime, s.period_multiple)


def _same_point(a, b) -> None:
    """A batch point against the reference's: the same label and method; a settled one the same
    k, z and x1_max (a nonperiodic one's last window is chaotic, see above)."""
    assert (a.label, a.regime, a.method) == (b.label, b.regime, b.method), (a.value, a.label, b.label)
    if b.regime != "nonperiodic":
        assert (a.period_multiple, a.impacts_per_cycle) == (b.period_multiple, b.impacts_per_cycle)
        assert abs(a.x1_max - b.x1_max) <= X1_TOL * max(1.0, abs(b.x1_max))


def test_random_starts_batch_matches_the_reference():
    """The batch's random starts are the reference's (the same seeded states), settled to the
    same motions, the Newton rescue included: at -10 the 3/2 cycle is reached only by it."""
    base = Parameters()
    settings = SweepSettings(settle_tol=1e-9, max_periods=150, max_periods_after_nonperiodic=50, continuation=False)
    values = [-20.0, -10.0, -5.8, 5.0]
    batch = random_starts_batch(base, "gap", values, 2, 20190105, indices=[3, 4, 5, 6], settings=settings)
    python = dataclasses.replace(settings, backend="python")
    ref = [
        [solve_point(p, v, state=state, settings=python, start="random") for state in states]
        for v, p, states in random_start_states(base, "gap", values, 2, 20190105, [3, 4, 5, 6])
    ]
    for row_a, row_b in zip(batch, ref):
        for a, b in zip(row_a, row_b):
            assert np.array_equal(a.start_state, b.start_state)
            _same_point(a, b)
    assert any(pt.method == "rescue" for row in batch for pt in row)


@pytest.mark.slow
def test_two_chains_are_the_reference_sweeps_both_ways():
    """A theta sweep up and one down as two chains of one call (``chain_length``): the points
    are the reference's two-way sweep without accelerators."""
    base = Parameters()
    settings = SweepSettings(settle_tol=1e-9, max_periods=150, max_periods_after_nonperiodic=50, continuation=False)
    thetas = np.linspace(0.9, 1.3, 9)
    res = idp.steady_states(base, ("theta",), np.r_[thetas, thetas[::-1]][:, None], settings=settings, chain_length=9)
    b = two_way_sweep(base, "theta", thetas, settings=dataclasses.replace(settings, backend="python"))
    for i, y in zip(list(range(9)) + list(range(17, 8, -1)), b["up"] + b["down"]):
        assert (res.label[i], res.regime[i], res.method[i]) == (y.label, y.regime, y.method), (y.value, y.label)
        if y.regime != "nonperiodic":
            assert (res.period_multiple[i], res.impacts_per_cycle[i]) == (y.period_multiple, y.impacts_per_cycle)
            assert abs(res.x1_max[i] - y.x1_max) <= X1_TOL * max(1.0, abs(y.x1_max))


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(chain=True, states=[[0.0, -5.8, 0.0, 0.0]] * 2),  # one start per chain: here one chain
        dict(chain=False, states=[[0.0, -5.8, 0.0]]),
        dict(chain=False, states=[[0.0, -5.8, 0.0, 0.0], [0.0, -5.8, 0.0, 0.0]]),
        dict(chain=False, states=[[0.0, -5.0, 0.0, 0.0]]),  # x2 - x1 > Delta0: the bodies overlap
        dict(chain=False, states=[[0.0, math.inf, 0.0, 0.0]]),
    ],
)
def test_bad_start_states(kwargs):
    with pytest.raises(ValueError, match="`states`"):
        idp.steady_states(Parameters(), ("gap",), [[-5.8]], **kwargs)


def test_rescue_from_sections_is_the_rescue_without_accelerators():
    with pytest.raises(ValueError, match="`settings`"):
        rescue_from_sections(
            Parameters(),
            -10.0,
            np.zeros((17, 4)),
            np.zeros(4),
            "free",
            SweepSettings(),
            start="",
            start_state=np.zeros(4),
            periods=1,
        )


@pytest.mark.parametrize("gap", [-5.8, -9.6, -13.0, -20.0, -33.0, 12.0])
def test_compiled_settle_described_by_the_reference_is_the_reference(gap):
    """The compiled backend's settle with the cycle described by the reference (the sweeps'
    ladder: the period loop compiled, describe_run on the kernels' run) against steady_state:
    the same regime, k, periods and cycle (impact times to PHASE_TOL T, x1_max to X1_TOL), the
    same sections to rounding; a nonperiodic (chaotic) run only its verdict."""
    p = Parameters(gap=gap)
    options = SettleOptions(max_periods=400, describe="reference")
    a, b = get_backend("compiled")[0].settle(p, 0.0, None, Tolerances(), options), steady_state(p, max_periods=400)
    assert (a.regime, a.period_multiple, a.periods) == (b.regime, b.period_multiple, b.periods)
    assert a.sections.shape == b.sections.shape
    if b.settled:
        assert len(a.impacts) == len(b.impacts)
        assert max([abs(x.t - y.t) / p.T for x, y in zip(a.impacts, b.impacts)] + [0.0]) <= PHASE_TOL
        assert abs(a.x1_max - b.x1_max) <= X1_TOL
        assert np.max(np.abs(a.sections[:5] - b.sections[:5])) <= 1e-9 * np.max(np.abs(b.sections[:5]))


def test_sweep_with_the_compiled_loop_is_the_reference():
    """solve_point's simulations by the compiled backend (SweepSettings.backend "auto", the default)
    against the pure-Python ones, accelerators on, along a gap sweep through the chaotic band.

    A point started from its neighbour may wander through a chaotic transient before it lands
    on its cycle (at -13 from -14's 2/1 motion the pure-Python run lands on the chatter cycle
    c/3 after ~100 periods): there the two loops' rounding differences grow until the two runs
    are different motions, and whether each lands within the cap (150 periods) is chance.
    Such a point is nonperiodic in one run and settled in the other; every other point agrees
    (measured: 2 of 22 differ, at -13 down and at -8 up on the record's CPU, at -13 up and down
    on an AMD EPYC; -8 starts from -9's nonperiodic motion, whose last section differs between
    the two runs). Which points of the chaotic band differ is decided at the last bits (the
    kernels are compiled for the host CPU), so the test names the band and a count, not the
    points. How a point was reached (method, periods) may then differ further along the path."""
    base = Parameters()
    gaps = np.linspace(-14.0, -4.0, 11)
    a = two_way_sweep(base, "gap", gaps, settings=SweepSettings())
    b = two_way_sweep(base, "gap", gaps, settings=SweepSettings(backend="python"))
    differ = []
    for direction in ("up", "down"):
        for x, y in zip(a[direction], b[direction]):
            if x.label != y.label and "nonperiodic" in (x.regime, y.regime):
                differ.append((direction, x.value))
                continue
            # (How a point was reached, and in how many periods, follows the path: after -13
            # the two sweeps start -14 from different motions.)
            assert x.label == y.label, (x.value, x.label, y.label)
            if y.regime != "nonperiodic":  # (a chaotic run's last window is not compared, see above)
                assert (x.period_multiple, x.impacts_per_cycle) == (y.period_multiple, y.impacts_per_cycle)
                assert abs(x.x1_max - y.x1_max) <= X1_TOL * max(1.0, abs(y.x1_max))
    assert all(-13.0 <= gap <= -8.0 for _, gap in differ) and len(differ) <= 3, differ  # (the chaotic band)


def test_fallback_is_counted():
    """A double root of eq. (4) has no modal form: the point goes to the reference, and says so."""
    delta2 = HARD["repeated_roots"].changes["delta2"]
    p = Parameters(N=0.9, delta2=delta2)
    settings = SweepSettings(max_periods=40, max_periods_after_nonperiodic=30, rescue=False, continuation=False)
    res = idp.steady_states(p, ("gap",), [[-5.8]], settings=settings)
    assert res.fallbacks == {"matrix_exponential": 1}
    ref = solve_point(p, settings=settings)
    assert (res.regime[0], res.periods[0]) == (ref.regime, ref.periods)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(names=("nope",), values=[[1.0]]), "names"),
        (dict(names="gap", values=[[1.0]]), "names"),
        (dict(names=("gap",), values=[[math.nan]]), "values"),
        (dict(names=("gap",), values=[[1.0]], chain=1), "chain"),
        (dict(names=("theta",), values=[[-1.0]]), "theta"),
    ],
)
def test_bad_batch_arguments(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        idp.steady_states(Parameters(), **kwargs)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: idp.steady_state(Parameters(), max_periods=1, backend="compiled"), "max_periods"),
        (lambda: idp.steady_state(Parameters(), settle_tol=2.0, backend="compiled"), "settle_tol"),
        (lambda: idp.steady_state(Parameters(), t0=math.inf, backend="compiled"), "t0"),
        (lambda: idp.steady_state("reference", backend="compiled"), "p"),
        (lambda: idp.simulate(Parameters(), -1.0, backend="compiled"), "t_end"),
        (lambda: idp.simulate(Parameters(), 1.0, state=[0.0, 10.0, 0.0, 0.0], backend="compiled"), "state"),
    ],
)
def test_bad_compiled_arguments(call, name):
    """The compiled backend's calls name a bad argument as the reference does."""
    with pytest.raises(ValueError, match=f"`{name}`"):
        call()


# --- numba's cache kept in step with the sources ------------------------------------------
def test_stale_kernel_cache_is_cleared(tmp_path):
    """A changed source (any of the package's, not only the kernel's own file, which is all that
    numba checks) removes the cached kernels; unchanged sources keep them."""
    from impactdamper.core.compiled.cache import STAMP_NAME, _clear_if_stale

    src = tmp_path / "compiled"
    src.mkdir()
    (src / "flow.py").write_text("A = 1\n")
    (tmp_path / "events.py").write_text("MAX_STEPS = 200000\n")
    sources = [src / "flow.py", tmp_path / "events.py"]
    cache = src / "__pycache__"
    assert _clear_if_stale(cache, sources) is False  # nothing cached yet: stamped
    kernels = [cache / "loop.advance-1.py311.nbi", cache / "loop.advance-1.py311.1.nbc"]
    for f in kernels:
        f.write_bytes(b"kernel")
    assert _clear_if_stale(cache, sources) is False and all(f.exists() for f in kernels)
    (tmp_path / "events.py").write_text("MAX_STEPS = 100000\n")  # a constant the kernels freeze
    assert _clear_if_stale(cache, sources) is True
    assert not any(f.exists() for f in kernels) and (cache / STAMP_NAME).is_file()
    assert _clear_if_stale(cache, sources) is False


def test_kernel_cache_is_stamped_with_the_sources():
    """The package's own cache carries the digest of the sources it was compiled from."""
    from pathlib import Path

    from impactdamper.core.compiled import cache

    here = Path(cache.__file__).resolve().parent
    stamp = here / "__pycache__" / cache.STAMP_NAME
    sources = sorted(here.glob("*.py")) + sorted(here.parent.glob("*.py"))
    assert stamp.read_text().strip() == cache._sources_digest(sources)
