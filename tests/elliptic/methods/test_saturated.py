"""The saturated linear theory: Kalker's linear forces at vanishing creepage, the friction limit never exceeded,
Shen, Hedrick & Elkins' cubic, the full-slip moment of pure spin in closed form, signs, and its error estimate against
the discretised level."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact import EllipticScene, ExponentialFalling, Material, solve_elliptic
from rollcontact.elliptic.methods.saturated import saturation_factor, spin_limit


def scene(ratio=1.0, friction=0.3, **creepages):
    c = 6e-3
    return EllipticScene.from_semi_axes(1e5, c * math.sqrt(ratio), c / math.sqrt(ratio),
                                        material=Material(210e9, 0.28), friction=friction, **creepages)


def test_the_linear_theory_at_vanishing_creepage():
    s = scene(2.0, longitudinal_creepage=1e-8, lateral_creepage=-2e-8, spin_creepage=1e-7)
    saturated, linear = solve_elliptic(s, "saturated"), solve_elliptic(s, "linear")
    for name in ("longitudinal_force", "lateral_force", "spin_moment"):
        assert math.isclose(getattr(saturated, name), getattr(linear, name), rel_tol=1e-5), \
            f"{name}: the saturation factor is 1 - u/3 + O(u^2), u below 1e-5 here"


@pytest.mark.parametrize("ratio", [0.2, 1.0, 5.0])
def test_the_force_never_exceeds_the_friction_limit_and_reaches_it(ratio):
    rng = np.random.default_rng(7)
    limit = 0.3 * 1e5
    for _ in range(200):
        xi, eta = rng.normal(0.0, 0.01, 2)
        phi = rng.normal(0.0, 2.0)
        r = solve_elliptic(scene(ratio, longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi),
                           "saturated")
        assert math.hypot(r.longitudinal_force, r.lateral_force) <= limit * (1 + 1e-12), \
            f"|F| = {math.hypot(r.longitudinal_force, r.lateral_force)} above mu Fn at {xi, eta, phi}"
    deep = solve_elliptic(scene(ratio, longitudinal_creepage=1.0), "saturated")
    assert math.isclose(deep.longitudinal_force, limit, rel_tol=1e-12), "full slip: Fx = mu Fn"


def test_a_falling_law_is_bounded_by_its_largest_coefficient():
    law = ExponentialFalling(0.6557, 0.4, 0.6)
    r = solve_elliptic(scene(friction=law, longitudinal_creepage=-0.0046, rolling_speed=10.0), "saturated")
    assert abs(r.longitudinal_force) <= law.maximum_coefficient * 1e5, "|Fx| <= mu_max Fn"


def test_shen_hedrick_elkins_cubic():
    for u in (0.0, 0.5, 1.0, 2.0, 2.999):
        assert math.isclose(u * saturation_factor(u), u - u**2 / 3 + u**3 / 27, abs_tol=1e-15), f"g({u})"
    assert saturation_factor(3.0) * 3.0 == 1.0 and saturation_factor(10.0) * 10.0 == 1.0, "g = 1 from u = 3 on"
    assert saturation_factor(3.0 - 1e-9) * (3.0 - 1e-9) == pytest.approx(1.0, abs=1e-15), "g is continuous at 3"


def test_the_moment_of_pure_spin_saturates_at_the_full_slip_moment():
    """A circle in full slip under pure spin: Mz = mu Fn (3 pi / 16) a (the mean radius under Hertz's pressure)."""
    s = scene(1.0, spin_creepage=1e4)
    a = s.hertz.a
    assert math.isclose(spin_limit(s), 0.3 * 1e5 * 3 * math.pi / 16 * a, rel_tol=1e-12), "M_s of a circle"
    assert math.isclose(solve_elliptic(s, "saturated").spin_moment, spin_limit(s), rel_tol=1e-12), \
        "deep pure spin: the moment is M_s"


def test_signs_and_symmetry():
    base = dict(longitudinal_creepage=2e-3, lateral_creepage=-1e-3, spin_creepage=0.5)
    r = solve_elliptic(scene(0.5, **base), "saturated")
    m = solve_elliptic(scene(0.5, **{k: -v for k, v in base.items()}), "saturated")
    for name in ("longitudinal_force", "lateral_force", "spin_moment"):
        assert getattr(m, name) == -getattr(r, name), f"{name} is odd in the creepages"
    assert r.longitudinal_force > 0, "xi > 0 gives Fx > 0 on the rail"


@pytest.mark.slow
def test_the_error_estimate_bounds_the_error_against_the_discretised_level():
    """A handful of the calibration's cases: linear range, saturation, spin alone and with creepage."""
    for ratio in (0.2, 1.0, 5.0):
        for creepages in ({"longitudinal_creepage": 2e-4}, {"lateral_creepage": 5e-3}, {"spin_creepage": 0.3},
                          {"longitudinal_creepage": 1e-3, "spin_creepage": 2.0}):
            s = scene(ratio, **creepages)
            r = solve_elliptic(s, "saturated")
            reference = solve_elliptic(s, "discretised", elements=32)
            error = max(abs(a - b) for a, b in zip(r.force_coefficients, reference.force_coefficients, strict=True))
            assert error <= r.info["error_estimate"] + reference.info["error_estimate"], \
                f"a/b {ratio}, {creepages}: error {error:.3g} beyond the estimate {r.info['error_estimate']:.3g}"
