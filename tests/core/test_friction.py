"""Friction laws mu(v) (docs/physics.md, Velocity-dependent friction)."""

import numpy as np
import pytest

import rollcontact as rc
from rollcontact.core.friction import RAIL_CONDITIONS, friction_from_dict

V = np.linspace(0.0, 20.0, 401)  # slip velocity [m/s]

LAWS = {
    "coulomb": rc.Coulomb(0.3),
    "exponential": rc.ExponentialFalling(0.3, kinetic_ratio=0.4, decay=0.6),
    "rational": rc.RationalFalling(0.3, mu_kinetic=0.15, reference_velocity=2.0),
    "linear": rc.LinearFalling(0.3, mu_kinetic=0.1, slope=0.02),
    "table": rc.TabulatedFriction(velocities=(0.0, 1.0, 5.0), coefficients=(0.3, 0.25, 0.12)),
}


@pytest.mark.parametrize("name", list(LAWS))
def test_static_value_monotone_fall_and_bounds(name):
    law = LAWS[name]
    mu = law.coefficient(V)
    assert law.static_coefficient == pytest.approx(0.3, rel=1e-15), f"{name}: mu(0) = mu_s"
    assert np.all(np.diff(mu) <= 1e-15), f"{name}: falling (non-increasing) in v"
    assert np.all(mu > 0) and np.all(mu <= 0.3 + 1e-15), f"{name}: 0 < mu <= mu_s"
    assert law.is_constant == (name == "coulomb"), f"{name}: is_constant"


@pytest.mark.parametrize("name", ["exponential", "rational"])
def test_analytic_derivative_matches_differences(name):
    law = LAWS[name]
    v = np.array([0.1, 0.5, 2.0, 7.0])
    h = 1e-6
    fd = (law.coefficient(v + h) - law.coefficient(v - h)) / (2 * h)
    np.testing.assert_allclose(law.derivative(v), fd, rtol=1e-6, err_msg=f"{name}: dmu/dv")


def test_exponential_law_is_polach_form():
    law = LAWS["exponential"]
    v_half = np.log(2.0) / law.decay
    mu_k = law.mu_static * law.kinetic_ratio
    np.testing.assert_allclose(law.coefficient(v_half), mu_k + 0.5 * (law.mu_static - mu_k), rtol=1e-14,
                               err_msg="mu_k + mu_e exp(-ln2 v / v_half) at v = v_half")
    np.testing.assert_allclose(law.coefficient(1e6), mu_k, rtol=1e-12, err_msg="mu(inf) = A mu_s")


@pytest.mark.parametrize("data, law", [
    ({"law": "coulomb", "mu": 0.2}, rc.Coulomb(0.2)),
    ({"law": "rational", "mu_static": 0.3, "mu_kinetic": 0.15, "reference_velocity": 2.0}, LAWS["rational"]),
    ({"law": "linear", "mu_static": 0.3, "mu_kinetic": 0.1, "slope": 0.02}, LAWS["linear"]),
    ({"law": "table", "velocities": [0.0, 1.0, 5.0], "coefficients": [0.3, 0.25, 0.12]}, LAWS["table"]),
])
def test_from_toml_table(data, law):
    assert friction_from_dict(data) == law, f"{data} -> {law}"


@pytest.mark.parametrize("make, match", [
    (lambda: rc.Coulomb(-0.1), "mu"),
    (lambda: rc.Coulomb(float("nan")), "mu"),
    (lambda: rc.ExponentialFalling(0.3, kinetic_ratio=1.5), "kinetic_ratio"),
    (lambda: rc.ExponentialFalling(0.3, decay=-1.0), "decay"),
    (lambda: rc.RationalFalling(0.3, 0.1, 0.0), "reference_velocity"),
    (lambda: rc.TabulatedFriction((0.0, 0.0), (0.3, 0.2)), "increase"),
    (lambda: rc.TabulatedFriction((0.0, 1.0), (0.3,)), "equally many"),
    (lambda: friction_from_dict({"law": "stribeck"}), "valid laws"),
])
def test_bad_parameters_raise_naming_the_value(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_falling_friction_law_drives_the_polynomial_solver():
    """Any law plugs into the solver: a table law equal to the exponential one gives the same T'."""
    exp_law = LAWS["exponential"]
    v = np.linspace(0.0, 2.0, 2001)
    table = rc.TabulatedFriction(tuple(v), tuple(exp_law.coefficient(v)))
    base = rc.Scene(normal_load_per_length=1e6, creep=1e-3, rolling_speed=20.0)
    t_exp = rc.solve(base.replace(friction=exp_law)).tangential_force_per_length
    t_tab = rc.solve(base.replace(friction=table)).tangential_force_per_length
    np.testing.assert_allclose(t_tab, t_exp, rtol=1e-6, err_msg="table law vs exponential law")


@pytest.mark.parametrize(("name", "says"), [
    ("coulomb", ("Coulomb", "mu = 0.3")),
    ("exponential", ("exponential falling", "mu_s = 0.3", "A = 0.4", "B = 0.6 s/m")),
    ("rational", ("rational falling", "mu_s = 0.3", "mu_k = 0.15", "v_ref = 2 m/s")),
    ("linear", ("linear falling", "mu_s = 0.3", "mu_k = 0.1", "c = 0.02 s/m")),
    ("table", ("tabulated", "3 points", "0.3 at v = 0 m/s", "0.12 at 5 m/s")),
])
def test_describe_names_the_law_and_its_values_with_units(name, says):
    text = LAWS[name].describe()
    assert all(part in text for part in says) and "\n" not in text, f"{name}: {text!r} must say {says}"


@pytest.mark.parametrize(("name", "values"), [("dry", (0.55, 0.40, 0.60)), ("wet", (0.30, 0.40, 0.20))])
def test_rail_conditions_are_polachs_published_sets(name, values):
    """Polach 2005 (Wear 258, Table 2): mu_0, A, B [s/m] of dry and wet rail, as the exponential law."""
    condition = RAIL_CONDITIONS[name]
    assert (condition.mu_static, condition.kinetic_ratio, condition.decay) == values, f"{name}: {condition}"
    assert "Polach" in condition.source and "Wear 258" in condition.source, f"{name}: source {condition.source!r}"
    law = rc.rail_condition(name.upper())
    assert law == rc.ExponentialFalling(*values), f"{name}: rail_condition gives {law!r}"
    np.testing.assert_allclose(law.coefficient(1e6), values[0] * values[1], rtol=1e-12,
                               err_msg=f"{name}: mu(inf) = A mu_0")


def test_a_rail_condition_is_a_whole_toml_law_and_unknown_names_are_listed():
    assert friction_from_dict({"rail_condition": "wet"}) == rc.ExponentialFalling(0.3, 0.4, 0.2), "wet from TOML"
    with pytest.raises(ValueError, match="valid conditions are \\['dry', 'wet'\\]"):
        rc.rail_condition("icy")
    with pytest.raises(ValueError, match="rail_condition = 'dry' sets the whole law; remove decay, law"):
        friction_from_dict({"rail_condition": "dry", "law": "exponential", "decay": 0.3})
