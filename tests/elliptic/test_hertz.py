"""Hertz's ellipse against independent oracles: the Boussinesq integral of the Hertz pressure (its displacement must
be ``delta - A x^2 - B y^2`` in the ellipse), the load balance, the sphere, and the inverse (from semi-axes).

Oracle: the normal displacement of identical bodies under a pressure p is ``u(P) = (1/(pi E*)) int p / r dA``.  For
the ellipsoidal pressure, along each ray from P the pressure is ``p0 sqrt(quadratic in rho)`` and the radial integral
is closed-form (a circular segment), so u(P) is one smooth integral over the ray angle (composite Gauss-Legendre,
100 panels of 40 nodes: the integrand peaks along the long axis of a slender ellipse).
Tolerances: identities 1e-12; the quadrature oracle 1e-8.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact import Material
from rollcontact.elliptic.hertz import curvatures_from_radii, curvatures_from_semi_axes, hertz_ellipse
from rollcontact.elliptic.scene import EllipticScene

E_STAR = Material(210e9, 0.28).contact_modulus


def displacement(x0, y0, a, b, p0):
    """u(x0, y0) [m] of the pressure ``p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` on identical half-spaces (docstring)."""
    nodes, weights = np.polynomial.legendre.leggauss(40)
    panels = 100
    theta = (math.pi / panels * (nodes[None, :] + 1.0 + 2.0 * np.arange(panels)[:, None])).ravel()
    weights = np.tile(weights, panels) / panels
    c, s = np.cos(theta), np.sin(theta)
    # 1 - (x0 + rho c)^2/a^2 - (y0 + rho s)^2/b^2 = alpha - 2 beta rho - gamma rho^2
    gamma = c * c / a**2 + s * s / b**2
    beta = x0 * c / a**2 + y0 * s / b**2
    alpha = 1.0 - x0**2 / a**2 - y0**2 / b**2
    centre = -beta / gamma  # of the chord, rho from 0 to its far end
    half = np.sqrt(beta**2 + alpha * gamma) / gamma
    # int_0^{rho+} sqrt(gamma (h^2 - (rho - centre)^2)) drho
    segment = half**2 * math.pi / 4 + centre / 2 * np.sqrt(half**2 - centre**2) + half**2 / 2 * np.arcsin(centre / half)
    return p0 / (math.pi * E_STAR) * math.pi * np.sum(weights * np.sqrt(gamma) * segment)


@pytest.mark.parametrize(("A", "B"), [(1.0, 1.0), (1.0, 3.0), (2.0, 1.0), (0.5, 25.0), (40.0, 1.0)])
def test_the_hertz_pressure_makes_the_gap_it_closes(A, B):
    load = 5e4
    h = hertz_ellipse(load, A, B, E_STAR)
    assert math.isclose(2 / 3 * math.pi * h.a * h.b * h.max_pressure, load, rel_tol=1e-12), "load balance"
    u0 = displacement(0.0, 0.0, h.a, h.b, h.max_pressure)
    assert math.isclose(u0, h.approach, rel_tol=1e-8), f"approach {h.approach} vs Boussinesq {u0}"
    for fraction in (0.3, 0.7):
        ux = displacement(fraction * h.a, 0.0, h.a, h.b, h.max_pressure)
        uy = displacement(0.0, fraction * h.b, h.a, h.b, h.max_pressure)
        assert math.isclose((u0 - ux) / (fraction * h.a) ** 2, A, rel_tol=1e-8), f"A at x = {fraction} a"
        assert math.isclose((u0 - uy) / (fraction * h.b) ** 2, B, rel_tol=1e-8), f"B at y = {fraction} b"


def test_equal_curvatures_give_the_sphere():
    radius, load = 0.5, 1e4
    h = hertz_ellipse(load, 1 / (2 * radius), 1 / (2 * radius), E_STAR)
    expected = (3 * load * radius / (4 * E_STAR)) ** (1 / 3)
    assert math.isclose(h.a, expected, rel_tol=1e-13) and math.isclose(h.b, expected, rel_tol=1e-13), "sphere radius"
    assert math.isclose(h.approach, h.a**2 / radius, rel_tol=1e-12), "sphere approach a^2/R"
    nearly = hertz_ellipse(load, 1 / (2 * radius), 1 / (2 * radius) * (1 + 1e-12), E_STAR)
    assert math.isclose(nearly.a, expected, rel_tol=1e-11), "continuous at the sphere"


@pytest.mark.parametrize("ratio", [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0])
def test_semi_axes_round_trip_through_the_curvatures(ratio):
    a, load = 6e-3, 1e5
    A, B = curvatures_from_semi_axes(a, a / ratio, load, E_STAR)
    h = hertz_ellipse(load, A, B, E_STAR)
    assert math.isclose(h.a, a, rel_tol=1e-10) and math.isclose(h.b, a / ratio, rel_tol=1e-10), "inverse of Hertz"
    assert math.isclose(h.aspect_ratio, ratio, rel_tol=1e-10), "aspect ratio"
    assert (A < B) == (ratio > 1), "the longer semi-axis lies along the smaller curvature"


def test_the_aspect_ratio_follows_the_published_approximation():
    """Brewe & Hamrock (1977): b/a ~ (A/B)^(2/pi) for a along the smaller curvature, within a few per cent."""
    for curvature_ratio in (2.0, 5.0, 20.0):
        h = hertz_ellipse(1e4, 1.0, curvature_ratio, E_STAR)
        approximation = curvature_ratio ** (-2 / math.pi)
        assert abs(1 / h.aspect_ratio / approximation - 1) < 0.05, f"b/a at B/A = {curvature_ratio}"


def test_wheel_on_rail_radii():
    A, B = curvatures_from_radii(0.46, math.inf, 0.3)
    assert math.isclose(A, 0.5 / 0.46) and math.isclose(B, 0.5 / 0.3), "A = 1/(2 r0), B = 1/(2 r_rail)"
    A, B = curvatures_from_radii(0.46, -0.5, 0.3)
    assert math.isclose(B, 0.5 * (1 / 0.3 - 1 / 0.5)), "a concave wheel profile subtracts"
    scene = EllipticScene.from_radii(1e5, 0.46, rail_profile_radius=0.3)
    assert scene.hertz.a > scene.hertz.b, "rail crown 0.3 m, wheel 0.46 m: the ellipse is longer along x"


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"wheel_profile_radius": -0.2, "rail_profile_radius": 0.3}, "lateral curvature"),
    ({"wheel_rolling_radius": -0.46}, "wheel_rolling_radius"),
    ({"rail_profile_radius": 0.0}, "rail_profile_radius"),
    ({"wheel_profile_radius": math.nan}, "wheel_profile_radius"),
])
def test_bad_radii_are_refused_with_the_value(kwargs, match):
    args = {"wheel_rolling_radius": 0.46, **kwargs}
    with pytest.raises(ValueError, match=match):
        curvatures_from_radii(**args)


@pytest.mark.parametrize(("args", "match"), [((-1.0, 1.0, 1.0), "normal_load"), ((1.0, 0.0, 1.0), "longitudinal"),
                                             ((1.0, 1.0, -2.0), "lateral_curvature"), ((math.nan, 1.0, 1.0), "normal")])
def test_bad_hertz_input_is_refused_with_the_value(args, match):
    with pytest.raises(ValueError, match=match):
        hertz_ellipse(*args, E_STAR)


def test_zero_load_gives_a_point_with_the_aspect_ratio_of_any_load():
    h = hertz_ellipse(0.0, 1.0, 4.0, E_STAR)
    assert h.a == 0.0 and h.b == 0.0 and h.max_pressure == 0.0, "no load, no ellipse"
    assert math.isclose(h.aspect_ratio, hertz_ellipse(1e3, 1.0, 4.0, E_STAR).aspect_ratio), "a/b from the curvatures"
