"""The backend registry (impactdamper.core.backends): one place resolves a backend's name, a new
backend is one registry line, and the compiled run's trajectory is the reference's motion made
into objects only when read."""

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.core import backends
from impactdamper.core.compiled.layout import ERR_BUDGET, ERR_CAPACITY, ERR_DEGENERATE, ERR_SEARCH, MARCH_ROOT
from impactdamper.core.trajectory import EVENT_KINDS

REF = idp.Parameters()


def test_the_registry_names_the_backends():
    assert idp.BACKENDS == ("auto", "compiled", "python")
    assert backends.get_backend("auto") == (backends.get_backend("compiled")[0], "")
    assert backends.get_backend("python") == (backends.PYTHON, "")
    assert {b.name for b in (backends.get_backend(n)[0] for n in ("compiled", "python"))} == {"compiled", "python"}


def test_a_new_backend_is_one_registry_line(monkeypatch):
    """A backend registered under a new name is taken by every front-door call (here the
    reference under a second name)."""
    monkeypatch.setitem(backends.REGISTRY, "reference", "impactdamper.core.backends:PYTHON")
    s = idp.steady_state(REF, backend="reference", max_periods=300)
    assert (s.backend, s.fallback, s.regime) == ("python", "", "single_impact")
    assert idp.simulate(REF, REF.T, backend="reference").backend == "python"
    res = idp.steady_states(REF, ("gap",), [[-5.8]], backend="reference")
    assert (res.backend, res.label.tolist()) == ("python", ["1/1"])


def test_auto_without_numba_runs_the_reference_and_says_why(monkeypatch):
    monkeypatch.setitem(backends.REGISTRY, "compiled", "impactdamper.core.no_such_module:COMPILED")
    assert backends.get_backend("auto") == (backends.PYTHON, "numba_unavailable")
    s = idp.steady_state(REF, max_periods=300)
    assert (s.backend, s.fallback) == ("python", "numba_unavailable")
    traj = idp.simulate(REF, REF.T)
    assert (traj.backend, traj.fallback) == ("python", "numba_unavailable")
    res = idp.steady_states(REF, ("gap",), [[-5.8]])
    assert res.backend == "python" and res.fallback.tolist() == ["numba_unavailable"]


@pytest.mark.parametrize("bad", ["numba", "", None, 1, "Auto"])
def test_a_bad_name_is_named(bad):
    with pytest.raises(
        ValueError, match=r"^`backend` = .* is not allowed: must be one of 'auto', 'compiled', 'python' or a Backend$"
    ):
        backends.get_backend(bad)
    with pytest.raises(ValueError, match="^`backend`"):
        idp.analysis.point.SweepSettings(backend=bad)


def test_a_march_error_is_never_a_root():
    """The kernels' errors are numbered apart from the march's statuses: the step budget's
    error (ERR_BUDGET) was 1, read as a root at t = 0, and a run on the stop looped there
    without end (R = 1, theta = 0.5)."""
    assert MARCH_ROOT not in (ERR_BUDGET, ERR_SEARCH, ERR_DEGENERATE, ERR_CAPACITY)
    assert min(ERR_BUDGET, ERR_SEARCH, ERR_DEGENERATE, ERR_CAPACITY) > MARCH_ROOT


def test_compiled_trajectory_makes_its_objects_when_read():
    """A compiled run holds the kernels' arrays; sampling makes only the segments it reads, and
    its events, when read, are the reference's (kinds in order, times to 1e-9 T)."""
    traj = idp.simulate(REF, 30 * REF.T, backend="compiled")
    ref = idp.simulate(REF, 30 * REF.T, backend="python")
    assert traj._arrays is not None and not traj._made
    t = np.array([10.3, 10.6]) * REF.T
    assert np.max(np.abs(traj.sample(t)[0] - ref.sample(t)[0])) <= 1e-9 * REF.x_st * REF.omega
    assert 1 <= len(traj._made) <= 2 and traj._arrays is not None  # (only the segments sampled)
    assert [e.kind for e in traj.events] == [e.kind for e in ref.events]
    assert set(e.kind for e in traj.events) <= set(EVENT_KINDS)
    assert traj._arrays is None and len(traj.segments) == len(ref.segments)
    assert max(abs(a.t - b.t) for a, b in zip(traj.events, ref.events)) <= 1e-9 * REF.T


def test_buffers_grow_to_the_run():
    """A recorded run started with room for one event grows its buffers (within the work
    bound's allowance) to the same events as a run sized for them."""
    from impactdamper.core.compiled.layout import N_DIAG
    from impactdamper.core.compiled.loop import simulate_kernel
    from impactdamper.core.compiled.pack import pack_parameters

    p = idp.Parameters(theta=0.8)  # a chatter cycle: tens of events per period
    pk = pack_parameters(p)
    args = (pk.cm, pk.fm, pk.fc, pk.fk, pk.fg, pk.s, 0.0, idp.default_initial_state(p), 20 * p.T)
    small = simulate_kernel(*args, 1, np.zeros(N_DIAG))
    large = simulate_kernel(*args, 100_000, np.zeros(N_DIAG))
    assert small[0] == large[0] == 0 and len(small[1]) > 100
    assert all(np.array_equal(a, b) for a, b in zip(small[1:], large[1:]))


def test_the_architecture_page_lists_the_modules_of_core_and_analysis():
    """docs/ARCHITECTURE.md's library section quotes every module of core/ and analysis/ (as
    ``name.py``) and of core/compiled/ (by its name, ``backend.py`` as the backend object's
    file); tests/workflow/test_architecture.py holds every module it quotes to exist."""
    from pathlib import Path

    src = Path(idp.__file__).resolve().parent
    page = (src.parents[1] / "docs" / "ARCHITECTURE.md").read_text()
    section = page.split("## The library, bottom up")[1].split("## The workflow")[0]
    for name in ("core", "analysis"):
        modules = {f.name for f in (src / name).glob("*.py")} - {"__init__.py"}
        assert len(modules) > 10 and not [m for m in sorted(modules) if f"`{m}`" not in section], name
    kernels = {f.stem for f in (src / "core" / "compiled").glob("*.py")} - {"__init__", "backend"}
    assert len(kernels) > 5 and not [m for m in sorted(kernels) if f"`{m}`" not in section]
    assert "`backend.py`" in section
    from impactdamper.core import compiled as package_of_kernels

    assert len(package_of_kernels.__all__) <= 3
