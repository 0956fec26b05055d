"""Parameters: the paper's relative form, the dimensional values, and validation."""

import dataclasses
import math
import re

import numpy as np
import pytest

import impactdamper as idp
from impactdamper.core.parameters import PARAMETER_TABLE, REFERENCE, Parameters

# --- closed form first ---------------------------------------------------------------------


def test_defaults_are_the_reference_case():
    # "theta = 1; mu = 0.08; N = 0.5; delta1 = delta2 = 0.05; x_st = 1; R = 0.7;
    #  Delta0/x_st = -5.8; omega = 10 rad/s" (section "The results of the calculations").
    p = Parameters()
    assert p.to_dict() == {
        "theta": 1.0,
        "mu": 0.08,
        "N": 0.5,
        "delta1": 0.05,
        "delta2": 0.05,
        "R": 0.7,
        "gap": -5.8,
        "omega": 10.0,
        "x_st": 1.0,
        "m1": 1.0,
    }
    assert p == REFERENCE == idp.REFERENCE
    # Effective tuning 2 sqrt(c2/m2) = sqrt(c1/m1) = omega.
    assert math.isclose(2 * math.sqrt(p.c2 / p.m2), math.sqrt(p.c1 / p.m1), rel_tol=1e-15)
    assert math.isclose(math.sqrt(p.c1 / p.m1), p.omega, rel_tol=1e-15)
    assert (p.c1, p.c2, p.P0, p.Delta0, p.m2) == pytest.approx((100.0, 2.0, 100.0, -5.8, 0.08), rel=1e-15)
    assert p.T == 2 * math.pi / 10


@pytest.mark.parametrize("m1", [1.0, 37.5, 1e-3])
@pytest.mark.parametrize(
    "kw",
    [{}, {"theta": 0.3, "mu": 1e-4, "N": 50.0, "delta1": 0.0, "delta2": 2.0, "gap": 3.0, "omega": 123.0, "x_st": 0.01}],
)
def test_dimensional_values_give_back_the_relative_ones(m1, kw):
    p = Parameters(m1=m1, **kw)
    omega1 = math.sqrt(p.c1 / p.m1)
    omega2 = math.sqrt(p.c2 / p.m2)
    rel = 1e-14
    assert p.m2 / p.m1 == pytest.approx(p.mu, rel=rel)
    assert p.omega / omega1 == pytest.approx(p.theta, rel=rel)
    assert omega2 / omega1 == pytest.approx(p.N, rel=rel)
    assert p.k1 / (2 * p.m1 * omega1) == pytest.approx(p.delta1, rel=rel, abs=1e-300)
    assert p.k2 / (2 * p.m2 * omega1) == pytest.approx(p.delta2, rel=rel, abs=1e-300)
    assert p.P0 / p.c1 == pytest.approx(p.x_st, rel=rel)
    assert p.Delta0 / p.x_st == pytest.approx(p.gap, rel=rel)
    assert (p.omega1, p.omega2) == pytest.approx((omega1, omega2), rel=rel)
    assert p.h1 == pytest.approx(p.delta1 * omega1, rel=rel, abs=1e-300)  # h = k/(2m), eq. (5)
    assert p.h2 == pytest.approx(p.delta2 * omega1, rel=rel, abs=1e-300)
    assert p.reduced_mass == pytest.approx(p.m1 * p.m2 / (p.m1 + p.m2), rel=rel)


def test_replace_names_and_dict_round_trip():
    p = Parameters().replace(gap=-10.0, R=0.0)
    assert (p.gap, p.R, p.Delta0) == (-10.0, 0.0, -10.0)
    assert Parameters(**p.to_dict()) == p
    assert Parameters.names() == tuple(p.to_dict())
    assert Parameters.names()[:7] == ("theta", "mu", "N", "delta1", "delta2", "R", "gap")


def test_boundary_values_are_allowed():
    for kw in ({"R": 0.0}, {"R": 1.0}, {"delta1": 0.0, "delta2": 0.0}, {"gap": 0.0}, {"gap": -1e6}):
        Parameters(**kw)


# --- validation: one line naming the parameter, its value and the allowed range -------------

POSITIVE = ["theta", "mu", "N", "omega", "x_st", "m1"]
NON_NEGATIVE = ["delta1", "delta2"]

BAD = (
    [(name, value, "> 0") for name in POSITIVE for value in (0.0, -1.0)]
    + [(name, -1e-3, ">= 0") for name in NON_NEGATIVE]
    + [("R", -0.1, "[0, 1]"), ("R", 1.0000001, "[0, 1]")]
    + [(name, value, "finite") for name in Parameters.names() for value in (math.nan, math.inf, -math.inf)]
    + [(name, "1.0", "real number") for name in ("theta", "gap")]
    + [("R", True, "real number"), ("mu", None, "real number")]
)


@pytest.mark.parametrize("name, value, allowed", BAD)
def test_bad_value_raises_one_line_naming_it(name, value, allowed):
    with pytest.raises(ValueError) as info:
        Parameters(**{name: value})
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"`{name}` = {value!r} ")
    assert allowed in message


@pytest.mark.parametrize("name, value", [("gap", -20.0), ("mu", 0.0), ("R", 2.0)])
def test_replace_validates_too(name, value):
    p = Parameters()
    if name == "gap":
        assert p.replace(gap=value).gap == value
        return
    with pytest.raises(ValueError, match=f"^`{name}` = "):
        p.replace(**{name: value})


def test_replace_rejects_unknown_and_derived_names():
    for name in ("foo", "c1", "Delta0"):
        with pytest.raises(ValueError, match=f"^`{name}` is not a parameter: allowed are theta, mu"):
            Parameters().replace(**{name: 1.0})


@pytest.mark.parametrize(
    "kw, name, derived",
    [
        ({"theta": 1e-300}, "theta", "c1"),
        ({"theta": 1e-10, "omega": 1e300}, "omega", "omega1"),
        ({"theta": 1e300}, "theta", "c1"),
        ({"m1": 1e-300, "mu": 1e-30}, "m1", "m2"),
        ({"x_st": 1e-200, "omega": 1e-200}, "omega", "c1"),
        ({"delta1": 1e-300, "m1": 1e-30}, "delta1", "k1"),
    ],
)
def test_overflowing_relative_parameters_raise_one_line(kw, name, derived):
    # Regression: theta = 1e-300 used to escape as OverflowError from omega1**2, then named c1
    # (not a parameter a user sets): the message names the most extreme input.
    with pytest.raises(ValueError) as info:
        Parameters(**kw)
    message = str(info.value)
    assert message.startswith(f"`{name}` = {kw[name]!r} is not allowed") and f"dimensional {derived} = " in message
    assert "\n" not in message


# --- types, huge integers, numpy scalars, the reduced mass at extreme scales ---------
@pytest.mark.parametrize("value", [10**400, -(10**400)])
def test_huge_integer_is_a_named_error_not_overflow(value):
    with pytest.raises(ValueError, match=r"^`gap` = an integer of 401 digits is not allowed: must be a finite number"):
        Parameters(gap=value)


@pytest.mark.parametrize("value", [np.float32(1.25), np.float64(1.25), np.int64(1), np.int32(2), 3])
def test_numpy_scalars_are_numbers_stored_as_float(value):
    p = Parameters(theta=value, gap=value)
    assert type(p.theta) is float and p.theta == float(value) and p.Delta0 == float(value)
    assert Parameters(theta=value) == Parameters(theta=float(value))


@pytest.mark.parametrize("value", [True, False, np.bool_(True), "1.0", None, [1.0], 1 + 0j])
def test_non_numbers_are_type_errors_naming_the_field(value):
    with pytest.raises(TypeError, match=r"^`mu` = .* is not allowed: must be a real number$"):
        Parameters(mu=value)
    with pytest.raises(ValueError):  # the same error is a ValueError too (the command line catches those)
        Parameters(mu=value)


@pytest.mark.parametrize("m1", [1e-300, 1e300])
def test_reduced_mass_at_extreme_mass_scales(m1):
    p = Parameters(m1=m1)
    assert p.reduced_mass == pytest.approx(m1 * 0.08 / 1.08, rel=1e-14)


def test_damping_that_underflows_is_an_error_not_zero():
    # k1 = 2 m1 omega1 delta1 underflowing to 0 would silently drop the damping.
    with pytest.raises(ValueError, match=r"^`delta1` = 1e-300 .*dimensional k1 = .* underflows to 0"):
        Parameters(delta1=1e-300, m1=1e-30)
    assert Parameters(delta1=0.0).k1 == 0.0


def test_canonical_scales():
    p = Parameters(x_st=1e-200, m1=1e300, omega=3.0, gap=-7.0)
    assert not p.native_scales() and Parameters().native_scales()
    q = p.canonical()
    assert (q.x_st, q.m1, q.omega) == (1.0, 1.0, 10.0) and (q.gap, q.theta, q.mu) == (-7.0, 1.0, 0.08)


# --- the parameter table ---------------------------------------------------------------------
def test_the_table_is_the_dataclass_fields_in_order():
    fields = [f.name for f in dataclasses.fields(Parameters) if f.init]
    assert [s.name for s in PARAMETER_TABLE] == fields == list(Parameters.names())
    assert {s.role for s in PARAMETER_TABLE} == {"linear", "impact", "scale"}


@pytest.mark.parametrize("spec", PARAMETER_TABLE, ids=lambda s: s.name)
def test_each_range_of_the_table_is_checked_by_name(spec):
    bad = {"> 0": 0.0, ">= 0": -1e-3, "in [0, 1]": 1.5}.get(spec.allowed)
    if bad is None:
        assert getattr(Parameters(**{spec.name: -1e6}), spec.name) == -1e6  # any finite value
        return
    with pytest.raises(ValueError, match=rf"^`{spec.name}` = .* is not allowed: must be {re.escape(spec.allowed)}$"):
        Parameters(**{spec.name: bad})


def test_packed_columns_are_read_by_name():
    import inspect

    from impactdamper.core.compiled import pack

    assert pack.PARAMETER_COLUMNS == Parameters.names()
    # No column is read by position (the packing of one set and of many alike).
    assert not re.findall(r"\bv\[:?, ?\d+\]|\bv\[\d+\]", inspect.getsource(pack))
    for const, name in (
        (pack.C_THETA, "theta"),
        (pack.C_MU, "mu"),
        (pack.C_N, "N"),
        (pack.C_DELTA1, "delta1"),
        (pack.C_DELTA2, "delta2"),
        (pack.C_R, "R"),
        (pack.C_GAP, "gap"),
        (pack.C_OMEGA, "omega"),
        (pack.C_XST, "x_st"),
        (pack.C_M1, "m1"),
    ):
        assert pack.PARAMETER_COLUMNS[const] == name
    # Every value lands in its own name's column (all values distinct).
    p = Parameters(
        theta=1.1, mu=0.09, N=0.55, delta1=0.051, delta2=0.052, R=0.71, gap=-5.9, omega=11.0, x_st=1.2, m1=1.3
    )
    v, _, _ = pack.packing_values(p)
    assert {name: v[pack.PARAMETER_COLUMNS.index(name)] for name in Parameters.names()} == p.to_dict()


def test_cli_help_and_extremes_come_from_the_table():
    from impactdamper.cli import PARAMETER_HELP
    from impactdamper.core.parameters import LINEAR_PARAMETERS, RELATIVE_PARAMETERS, most_extreme

    assert list(PARAMETER_HELP) == list(Parameters.names())
    assert all(PARAMETER_HELP[s.name] == s.help for s in PARAMETER_TABLE)
    assert LINEAR_PARAMETERS == ("theta", "mu", "N", "delta1", "delta2")
    assert RELATIVE_PARAMETERS == LINEAR_PARAMETERS + ("R", "gap")
    # R (bounded) is no candidate by default; the farthest from the reference in decades is.
    assert most_extreme(Parameters(R=1e-12, mu=1e-3)) == "mu"
    assert most_extreme(Parameters(R=1e-12, mu=1e-3), RELATIVE_PARAMETERS) == "R"
