"""Polynomial method (Chebyshev and monomial bases) against closed forms and independent quadrature.

Oracles: Hertz/Carter for a parabolic gap; for other gaps the integral equations themselves by QUADPACK
(``(2/(pi E*)) PV-int p/(x - z) dz = h0'(x)`` in the patch, ``(2/(pi E*)) PV-int q/(x - z) dz = -xi`` in the stick
zone), load/force balance, the friction bound, the slip sign, the deformed gap outside the patch, and the
corrected closed formulas of docs/physics.md, Corrugated surface (eqs 28-31) evaluated here with scipy.special.j0/j1.
Tolerances: parabolic identities 1e-12; quadrature of the integral equations 1e-8 of a/R (pressure) and 1e-7
of xi (stick zone); truncation 1e-10 at the default order.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from quadrature import edge_quad, pressure_integral, pv_hilbert
from scipy.optimize import minimize_scalar
from scipy.special import j0, j1, jv

import rollcontact as rc
from rollcontact import (
    ExponentialFalling,
    Harmonic,
    Material,
    Scene,
    Surface,
    solve,
)
from rollcontact.line.methods.polynomial import chebyshev, slip, solver, validity

MATERIAL = Material(210e9, 0.28)
E_STAR = MATERIAL.contact_modulus
RADIUS = 0.46
MU = 0.3
LOAD = 1.0e6
A_HERTZ = math.sqrt(4 * LOAD * RADIUS / (math.pi * E_STAR))
XI_SAT = MU * A_HERTZ / RADIUS


def gap_slope(scene, x):
    """Undeformed gap slope ``h0'(X) = (X - x_c)/R - Z'(X)`` at ``x = X - x_c`` (from Surface.slope)."""
    return x / scene.radius - scene.surface.slope(x + scene.axis_position)


def normal_residual(result, scene, points):
    """Largest ``|(2/(pi E*)) PV-int p/(x - z) dz - h0'(x)|`` over ``points``, by quadrature.

    Parameters
    ----------
    result : ContactResult
        Solution.
    scene : Scene
        Its scene.
    points : ndarray
        x inside the patch.

    Returns
    -------
    float
        The largest residual [1].
    """
    estar = scene.material.contact_modulus
    edges = [result.leading_edge, result.trailing_edge]
    return max(abs((2.0 / estar) * pv_hilbert(result.pressure, edges, x) - gap_slope(scene, x)) for x in points)


def stick_residual(result, scene, points):
    """Largest ``|(2/(pi E*)) PV-int q/(x - z) dz + xi|`` over stick-zone ``points``, by quadrature."""
    estar = scene.material.contact_modulus
    pieces = [result.leading_edge, result.leading_edge + 2 * result.stick_half_width, result.trailing_edge]
    return max(abs((2.0 / estar) * pv_hilbert(result.traction, pieces, x) + scene.creep) for x in points)


def interior_grid(result, n=2001):
    """x on Chebyshev points of the first kind across the patch (never exactly on an edge)."""
    theta = np.pi * (np.arange(n) + 0.5) / n
    return result.contact_offset + result.contact_half_width * np.cos(theta)[::-1]


def field_violations(result, mu, n=2001):
    """Worst violations of ``p >= 0``, ``|q| <= mu p`` and ``s xi >= 0`` (slip zone) on an interior grid.

    Returns
    -------
    tuple of float
        ``(min p / p0, max (|q| - mu p (1 + 1e-9)) / (mu p0), max (-s sign(xi)) / (mu a / R))``.
    """
    x = interior_grid(result, n)
    p, q = result.pressure(x), result.traction(x)
    p0 = result.max_pressure
    bound = float(np.max(np.abs(q) - mu * p * (1 + 1e-9))) / (mu * p0)
    if "stick_zones" in result.info:  # several patches: behind each patch's stick zone, inside the patch
        slip_zone = np.any([(x > zone[1]) & (x < patch[1])
                            for patch, zone in zip(result.info["patches"], result.info["stick_zones"], strict=True)],
                           axis=0)
    else:
        slip_zone = x > result.leading_edge + 2 * result.stick_half_width
    s = result.slip(x[slip_zone]) * math.copysign(1.0, result.creep) if result.creep else np.zeros(1)
    s_scale = mu * result.contact_half_width / RADIUS
    return float(np.min(p)) / p0, bound, float(np.max(-s, initial=0.0)) / s_scale


def deformed_gap_minimum(result, scene, reach, m=120, nodes=800):
    """Smallest deformed gap outside the patch, relative to a^2/R, integrating its slope.

    Outside the patch the gap slope is ``h0'(x) - (2/(pi E*)) int p(z)/(x - z) dz`` (a regular integral, here by
    Gauss-Chebyshev quadrature of the second kind on ``result.pressure``); the gap is its integral from the edge
    (where it is zero) by the trapezoidal rule on a grid graded towards the edge.

    Parameters
    ----------
    result : ContactResult
        Solution.
    scene : Scene
        Its scene.
    reach : float
        How far beyond each edge to look [m].
    m : int
        Grid points per side.
    nodes : int
        Quadrature nodes across the patch.

    Returns
    -------
    float
        ``min gap / (a^2 / R)`` over both sides (0 when the gap stays open).
    """
    estar = scene.material.contact_modulus
    a, c = result.contact_half_width, result.contact_offset
    theta = np.pi * np.arange(1, nodes + 1) / (nodes + 1)
    z = c + a * np.cos(theta)
    weights = a * np.pi / (nodes + 1) * np.sin(theta) * result.pressure(z)  # int p g dz ~ sum weights g(z_i)
    worst = 0.0
    for side, edge in ((1.0, result.trailing_edge), (-1.0, result.leading_edge)):
        x = edge + side * reach * (np.arange(1, m + 1) / m) ** 2
        hilbert = (weights[None, :] / (x[:, None] - z[None, :])).sum(axis=1)
        slope = gap_slope(scene, x) - (2.0 / (math.pi * estar)) * hilbert
        xs = np.concatenate(([edge], x))
        ss = np.concatenate(([0.0], slope))
        gap = np.cumsum(0.5 * (ss[1:] + ss[:-1]) * np.diff(xs))
        worst = min(worst, float(np.min(gap)))
    return worst / (a * a / scene.radius)


def corrugation_closed_forms(scene, a, delta, a_star):
    """Corrected eqs 28-31 of docs/physics.md, Corrugated surface for the scene's harmonics (no polynomial part).

    Parameters
    ----------
    scene : Scene
        Harmonic surface.
    a, delta, a_star : float
        Half-width, offset (contact centre minus axis) and stick half-width [m].

    Returns
    -------
    tuple of float
        ``(N', Delta, |T'|, |xi|)`` from eqs 28, 29, 30, 31 with ``X0 = x_c + Delta``, ``Xs = X0 - a + a*``.
    """
    R, estar = scene.radius, scene.material.contact_modulus
    x0 = scene.axis_position + delta
    xs = x0 - a + a_star
    n_sum = d_sum = t_sum = xi_sum = 0.0
    for h in scene.surface.harmonics:
        k, phi, psi = h.wavenumber, h.cos_amplitude, h.sin_amplitude
        n_sum += a * k * j1(k * a) * (phi * math.cos(k * x0) + psi * math.sin(k * x0))
        d_sum += k * j0(k * a) * (psi * math.cos(k * x0) - phi * math.sin(k * x0))
        t_sum += a_star * k * j1(k * a_star) * (phi * math.cos(k * xs) + psi * math.sin(k * xs))
        xi_sum += k * j0(k * a_star) * (psi * math.cos(k * xs) - phi * math.sin(k * xs))
    mu = scene.friction_coefficient
    load = 0.5 * math.pi * estar * (a * a / (2 * R) + n_sum)
    offset = R * d_sum
    force = mu * load - mu * 0.5 * math.pi * estar * (a_star**2 / (2 * R) + t_sum)
    creep = mu * (a - a_star - delta) / R + mu * xi_sum
    return load, offset, force, creep


def corrugated_scene(ka, position, creep_fraction=0.4, amplitude_fraction=0.3, load=LOAD):
    """A one-harmonic scene with ``k a_Hertz = ka`` and amplitude ``amplitude_fraction / (R k^2)``.

    Parameters
    ----------
    ka : float
        k times the Hertz half-width.
    position : float
        Axis position as a fraction of the wavelength.
    creep_fraction : float
        xi as a fraction of the Hertz saturation creep mu a / R.
    amplitude_fraction : float
        Surface curvature amplitude A k^2 relative to 1/R (< 1 keeps the gap convex: one patch).
    load : float
        N' [N/m].

    Returns
    -------
    Scene
    """
    a = math.sqrt(4 * load * RADIUS / (math.pi * E_STAR))
    k = ka / a
    lam = 2 * math.pi / k
    harmonic = Harmonic.from_wavelength(lam, amplitude_fraction / (RADIUS * k * k), 0.3)
    return Scene(load, creep=creep_fraction * MU * a / RADIUS, radius=RADIUS, material=MATERIAL, friction=MU,
                 surface=Surface(harmonics=(harmonic,)), axis_position=position * lam)


def quartic_c4(a=A_HERTZ):
    """c4 with ``c4 a^4 = a^2 / (2R)``: the quartic term as large as the parabola at the Hertz edge."""
    return 1.0 / (2.0 * RADIUS * a * a)


POLY_SCENES = {
    "quartic": Scene(LOAD, creep=0.4 * XI_SAT, radius=RADIUS, material=MATERIAL, friction=MU,
                     surface=Surface(polynomial=(0.0, 0.0, 0.0, 0.0, -quartic_c4()))),
    "cubic+quartic": Scene(LOAD, creep=0.3 * XI_SAT, radius=RADIUS, material=MATERIAL, friction=MU,
                           surface=Surface(polynomial=(0.0, 0.0, 0.0, 0.5 * quartic_c4() * A_HERTZ, -quartic_c4()))),
    "cubic+quartic off-axis, negative creep": Scene(
        LOAD, creep=-0.6 * XI_SAT, radius=RADIUS, material=MATERIAL, friction=MU, axis_position=0.7 * A_HERTZ,
        surface=Surface(polynomial=(0.0, 0.0, 0.0, -0.8 * quartic_c4() * A_HERTZ, -quartic_c4()))),
}

KA_VALUES = [0.1, 0.3, 1.0, 3.0, 10.0]
POSITIONS = [0.0, 0.23, 0.61]


# ---------------------------------------------------------------------------------------------------------------
# parabolic gap: Hertz and Carter to round-off
@pytest.mark.parametrize("creep_fraction", [0.0, 0.35, -0.8, 1.7, -3.0])
def test_parabolic_gap_reproduces_hertz_carter_at_every_order(creep_fraction):
    scene = Scene(LOAD, creep=creep_fraction * XI_SAT, radius=RADIUS, material=MATERIAL, friction=MU,
                  surface=Surface(polynomial=(0.0, 1.3e-3)))
    exact = solve(scene, method="closed_form")
    a, p0 = exact.contact_half_width, exact.max_pressure
    x = exact.contact_offset + np.linspace(-1.1 * a, 1.1 * a, 200)  # no point exactly on an edge
    for order in range(1, 61):
        r = solve(scene, method="polynomial", order=order)
        tag = f"order {order}, xi = {scene.creep:.3e}"
        assert r.success and r.method == "polynomial", f"{tag}: {r.message}"
        for name in ("contact_half_width", "stick_half_width", "max_pressure", "contact_offset"):
            np.testing.assert_allclose(getattr(r, name), getattr(exact, name), rtol=1e-12, atol=1e-15 * a,
                                       err_msg=f"{tag}: {name}")
        np.testing.assert_allclose(r.tangential_force_per_length, exact.tangential_force_per_length, rtol=1e-12,
                                   atol=1e-12 * MU * LOAD, err_msg=f"{tag}: T'")
        np.testing.assert_allclose(r.pressure(x), exact.pressure(x), rtol=0, atol=1e-12 * p0,
                                   err_msg=f"{tag}: p(x)")
        np.testing.assert_allclose(r.traction(x), exact.traction(x), rtol=0, atol=1e-12 * p0,
                                   err_msg=f"{tag}: q(x)")
    inside = x[np.abs(x - exact.contact_offset) < a * (1 - 1e-9)]
    np.testing.assert_allclose(r.slip(inside), exact.slip(inside), rtol=0, atol=1e-12 * XI_SAT,
                               err_msg=f"xi = {scene.creep:.3e}: slip s(x) at order 60")
    if 0 < abs(creep_fraction) < 1:
        np.testing.assert_allclose(r.creep_stiffness_per_length, exact.creep_stiffness_per_length, rtol=1e-10,
                                   err_msg="creep stiffness")


@pytest.mark.parametrize("surface", [Surface(), Surface(harmonics=(Harmonic.from_wavelength(0.03, 1e-5, 0.4),))],
                         ids=["flat", "corrugated"])
def test_zero_creep_gives_zero_traction(surface):
    """At xi = 0 the whole patch sticks with T' = 0, so q must integrate to zero (Carter: q = 0 for a flat gap)."""
    scene = Scene(LOAD, creep=0.0, radius=RADIUS, material=MATERIAL, friction=MU, surface=surface)
    r = solve(scene, method="polynomial")
    assert r.success, r.message
    assert r.tangential_force_per_length == 0.0, f"T' = {r.tangential_force_per_length} at xi = 0"
    t = edge_quad(r.traction, [r.leading_edge, r.trailing_edge])
    assert abs(t) <= 1e-12 * MU * LOAD, f"int q dx = {t:.6e} N/m at xi = 0 but T' = 0 (mu N' = {MU * LOAD:.3e})"


def test_zero_load_polynomial_gives_no_contact():
    r = solve(corrugated_scene(1.0, 0.2, load=LOAD).replace(normal_load_per_length=0.0), method="polynomial")
    assert r.success, f"N' = 0 must succeed: {r.message}"
    assert r.tangential_force_per_length == 0.0 and r.contact_half_width == 0.0, f"no contact expected: {r}"
    assert np.all(r.pressure(np.linspace(-1e-3, 1e-3, 5)) == 0.0), "p must vanish at N' = 0"


# ---------------------------------------------------------------------------------------------------------------
# non-Hertzian polynomial gaps
@pytest.mark.parametrize("name", sorted(POLY_SCENES))
def test_polynomial_gap_solves_integral_equations(name):
    scene = POLY_SCENES[name]
    r = solve(scene, method="polynomial")
    assert r.success, f"{name}: {r.message}"
    a = r.contact_half_width
    if "cubic" in name:
        assert abs(r.contact_offset) > 1e-3 * a, f"{name}: an odd term must shift the contact: {r.contact_offset}"
    assert a < 0.95 * A_HERTZ, f"{name}: the quartic stiffens the gap, a = {a:.4e} vs Hertz {A_HERTZ:.4e}"
    np.testing.assert_allclose(pressure_integral(r), LOAD, rtol=1e-12, err_msg=f"{name}: int p dx = N'")
    pts = r.contact_offset + a * np.cos(np.linspace(0.07, math.pi - 0.07, 7))
    res = normal_residual(r, scene, pts)
    assert res <= 1e-8 * a / RADIUS, f"{name}: normal residual {res:.3e} > 1e-8 a/R = {1e-8 * a / RADIUS:.3e}"
    lead, a_star = r.leading_edge, r.stick_half_width
    assert 0 < a_star < a, f"{name}: expected partial slip, a* = {a_star}"
    stick_pts = lead + a_star * (1 + np.cos(np.linspace(0.2, math.pi - 0.2, 4)))
    res_t = stick_residual(r, scene, stick_pts)
    assert res_t <= 1e-7 * abs(scene.creep), f"{name}: stick residual {res_t:.3e} vs xi = {scene.creep:.3e}"
    t = edge_quad(r.traction, [lead, lead + 2 * a_star, r.trailing_edge])
    np.testing.assert_allclose(t, r.tangential_force_per_length, rtol=1e-10, err_msg=f"{name}: int q dx = T'")
    assert t * scene.creep > 0, f"{name}: T' must have the sign of xi"
    p_min, bound, slip_sign = field_violations(r, MU)
    assert p_min >= -1e-9, f"{name}: p < 0: min p/p0 = {p_min:.3e}"
    assert bound <= 0.0, f"{name}: |q| > mu p by {bound:.3e} mu p0"
    assert slip_sign <= 1e-9, f"{name}: slip opposes the creep in the slip zone ({slip_sign:.3e} mu a/R)"
    assert deformed_gap_minimum(r, scene, reach=3 * a) >= -1e-9, f"{name}: the gap closes outside the patch"


# ---------------------------------------------------------------------------------------------------------------
# corrugation
@pytest.mark.parametrize("position", POSITIONS)
@pytest.mark.parametrize("ka", KA_VALUES)
def test_corrugation_matches_integral_equation_and_closed_formulas(ka, position):
    scene = corrugated_scene(ka, position)
    r = solve(scene, method="polynomial")
    tag = f"k a = {ka}, x_c = {position} wavelength"
    assert r.success, f"{tag}: {r.message}"
    a, delta, a_star = r.contact_half_width, r.contact_offset, r.stick_half_width
    np.testing.assert_allclose(pressure_integral(r), LOAD, rtol=1e-11, err_msg=f"{tag}: int p dx = N'")
    pts = delta + a * np.cos(np.linspace(0.1, math.pi - 0.1, 5))
    res = normal_residual(r, scene, pts)
    assert res <= 1e-8 * a / RADIUS, f"{tag}: normal residual {res:.3e} > 1e-8 a/R"
    load, offset, force, creep = corrugation_closed_forms(scene, a, delta, a_star)
    np.testing.assert_allclose(load, LOAD, rtol=1e-12, err_msg=f"{tag}: eq 28 (N')")
    np.testing.assert_allclose(offset, delta, rtol=0, atol=1e-12 * a, err_msg=f"{tag}: eq 29 (Delta)")
    np.testing.assert_allclose(force, r.tangential_force_per_length, rtol=1e-11, atol=1e-12 * MU * LOAD,
                               err_msg=f"{tag}: eq 30 (T')")
    np.testing.assert_allclose(creep, scene.creep, rtol=1e-10, err_msg=f"{tag}: eq 31 (xi)")
    p_min, bound, slip_sign = field_violations(r, MU)
    assert p_min >= -1e-9 and bound <= 0.0 and slip_sign <= 1e-9, \
        f"{tag}: fields inadmissible: min p/p0 {p_min:.2e}, |q|-mu p {bound:.2e}, slip sign {slip_sign:.2e}"


@pytest.mark.parametrize("ka, position", [(0.3, 0.23), (3.0, 0.61), (10.0, 0.0)])
def test_corrugation_tangential_problem_by_quadrature(ka, position):
    scene = corrugated_scene(ka, position)
    r = solve(scene, method="polynomial")
    assert r.success, r.message
    lead, a_star = r.leading_edge, r.stick_half_width
    assert 0 < a_star < r.contact_half_width, f"expected partial slip, a* = {a_star}"
    res = stick_residual(r, scene, lead + a_star * (1 + np.cos(np.linspace(0.2, math.pi - 0.2, 4))))
    assert res <= 1e-7 * abs(scene.creep), f"stick residual {res:.3e} vs xi = {scene.creep:.3e}"
    t = edge_quad(r.traction, [lead, lead + 2 * a_star, r.trailing_edge])
    np.testing.assert_allclose(t, r.tangential_force_per_length, rtol=1e-10, err_msg="int q dx = T'")


@pytest.mark.parametrize("ka", [1.0, 10.0])
def test_corrugation_opposite_creep_mirrors(ka):
    plus = solve(corrugated_scene(ka, 0.23, creep_fraction=0.5), method="polynomial")
    minus = solve(corrugated_scene(ka, 0.23, creep_fraction=-0.5), method="polynomial")
    assert plus.success and minus.success, f"{plus.message} / {minus.message}"
    np.testing.assert_allclose(minus.tangential_force_per_length, -plus.tangential_force_per_length, rtol=1e-13,
                               err_msg="T'(-xi) = -T'(xi)")
    np.testing.assert_allclose(minus.stick_half_width, plus.stick_half_width, rtol=1e-13, err_msg="a*(-xi)")
    x = interior_grid(plus, 301)
    np.testing.assert_allclose(minus.traction(x), -plus.traction(x), rtol=0, atol=1e-12 * plus.max_pressure,
                               err_msg="q(-xi) = -q(xi)")


@pytest.mark.parametrize("ka", [1.0, 3.0])
def test_corrugation_creep_stiffness_equals_finite_difference(ka):
    scene = corrugated_scene(ka, 0.61)
    h = 1e-6 * scene.creep
    t_plus = solve(scene.replace(creep=scene.creep + h), method="polynomial").tangential_force_per_length
    t_minus = solve(scene.replace(creep=scene.creep - h), method="polynomial").tangential_force_per_length
    k = solve(scene, method="polynomial").creep_stiffness_per_length
    np.testing.assert_allclose(k, (t_plus - t_minus) / (2 * h), rtol=1e-6, err_msg="dT'/dxi vs central difference")


@pytest.mark.parametrize("ka", [3.0, 10.0])
def test_convergence_in_number_of_terms(ka):
    scene = corrugated_scene(ka, 0.23)
    ref = solve(scene, method="polynomial", order=80)
    x = interior_grid(ref, 401)
    p0 = ref.max_pressure
    orders = list(range(2, 41, 3))
    errors = []
    for order in orders:
        r = solve(scene, method="polynomial", order=order)
        errors.append(float(np.max(np.abs(r.pressure(x) - ref.pressure(x)))) / p0)
    report = ", ".join(f"{n}: {e:.1e}" for n, e in zip(orders, errors, strict=True))
    above_floor = [e for e in errors if e > 1e-13]
    assert len(above_floor) >= 4, f"too few orders above round-off to see convergence: {report}"
    ratios = [e2 / e1 for e1, e2 in zip(above_floor[:-1], above_floor[1:], strict=True)]
    assert all(q < 1.0 for q in ratios), f"error must decrease with the order: {report}"
    assert min(ratios) < 0.05, f"expected faster-than-geometric decay at high order: {report}"
    assert errors[-1] < 1e-12, f"order {orders[-1]} must reach round-off: {report}"
    default = solve(scene, method="polynomial")
    err = float(np.max(np.abs(default.pressure(x) - ref.pressure(x)))) / p0
    assert err <= 1e-10, f"default order {default.info.get('order')} error {err:.2e} > 1e-10 ({report})"
    err_q = float(np.max(np.abs(default.traction(x) - ref.traction(x)))) / p0
    assert err_q <= 1e-10, f"default order traction error {err_q:.2e} > 1e-10"


# ---------------------------------------------------------------------------------------------------------------
# conditioning
HALF_WIDTHS = [1e-4, 1e-3, 1e-2, 1e-1]


def scaled_scene(a, shape):
    """A scene whose Hertz half-width is ``a`` with a quartic/cubic or a corrugated profile scaled with a."""
    load = math.pi * E_STAR * a * a / (4 * RADIUS)
    if shape == "quartic":
        c4 = quartic_c4(a)
        surface = Surface(polynomial=(0.0, 0.0, 0.0, 0.5 * c4 * a, -c4))
    else:
        k = 3.0 / a
        surface = Surface(harmonics=(Harmonic.from_wavelength(2 * math.pi / k, 0.3 / (RADIUS * k * k), 0.4),))
    return Scene(load, creep=0.4 * MU * a / RADIUS, radius=RADIUS, material=MATERIAL, friction=MU, surface=surface,
                 axis_position=0.1 * a)


def compare(r, ref):
    """Largest relative difference of a, T' and the fields (relative to p0) between two results."""
    x = interior_grid(ref, 301)
    p0 = ref.max_pressure
    with np.errstate(all="ignore"):
        diffs = [abs(r.contact_half_width / ref.contact_half_width - 1),
                 abs(r.tangential_force_per_length / ref.tangential_force_per_length - 1),
                 float(np.max(np.abs(r.pressure(x) - ref.pressure(x)))) / p0,
                 float(np.max(np.abs(r.traction(x) - ref.traction(x)))) / p0]
    return max(diffs) if all(np.isfinite(diffs)) else math.inf


@pytest.mark.parametrize("shape", ["quartic", "corrugated"])
@pytest.mark.parametrize("a", HALF_WIDTHS)
def test_chebyshev_basis_holds_to_high_order(a, shape):
    scene = scaled_scene(a, shape)
    moderate = solve(scene, method="polynomial", order=30)
    assert moderate.success, f"a = {a}: {moderate.message}"
    for order in (60, 120):
        r = solve(scene, method="polynomial", order=order)
        assert r.success, f"a = {a}, order {order}: {r.message}"
        d = compare(r, moderate)
        assert d <= 1e-9, f"{shape}, a = {a:.0e} m: order {order} differs from order 30 by {d:.2e}"


def ka_scene(a, ka):
    """Hertz half-width ``a``, one harmonic with k a = ``ka`` and amplitude 0.3/(R k^2) (one patch)."""
    load = math.pi * E_STAR * a * a / (4 * RADIUS)
    k = ka / a
    surface = Surface(harmonics=(Harmonic.from_wavelength(2 * math.pi / k, 0.3 / (RADIUS * k * k), 0.4),))
    return Scene(load, creep=0.4 * MU * a / RADIUS, radius=RADIUS, material=MATERIAL, friction=MU, surface=surface,
                 axis_position=0.1 * a)


def test_monomial_basis_breaks_with_k_a_where_chebyshev_holds():
    """Where the paper's monomial form (eqs 21-26) breaks: measured, not asserted from theory.

    With the Taylor coefficients k^(j+1)/j! formed without overflow, the a^(2n) scaling of the matrix is harmless
    (a from 1e-4 to 1e-2 m behaves alike); what breaks the power basis is cancellation, which grows like
    (k a)^n / n!: exact to round-off for k a <= 3, a 5e-3 error at order 30 for k a = 10, and no solution at all
    (Newton fails on the noisy moments) for k a >= 20.  The Chebyshev basis is exact everywhere.
    """
    report, broken = [], set()
    for a in (1e-4, 1e-2):
        for ka in (1, 3, 10, 20, 40):
            scene = ka_scene(a, ka)
            ref = solve(scene, method="polynomial", order=int(1.5 * ka) + 40)
            assert ref.success, ref.message
            for order in (30, 60):
                with np.errstate(all="ignore"):
                    r = solve(scene, method="polynomial", order=order, basis="monomial")
                d = compare(r, ref) if r.success else math.inf
                cancel = r.info.get("cancellation_factor", math.nan)
                line = (f"a={a:.0e} m, k a={ka}, order {order}: success={r.success} error={d:.1e} "
                        f"cancellation_factor={cancel:.2e}")
                report.append(line)
                if ka <= 3:
                    assert r.success and d <= 1e-10, f"the monomial form holds for k a <= 3: {line}"
                if not (r.success and d <= 1e-3):
                    broken.add(ka)
            cheb = solve(scene, method="polynomial", order=60 + int(1.5 * ka))
            assert cheb.success and compare(cheb, ref) <= 1e-9, f"Chebyshev must hold: a={a}, k a={ka}"
    text = "\n".join(report)
    assert {20, 40} <= broken, f"the monomial form should break for k a >= 20:\n{text}"
    assert not broken & {1, 3}, f"and hold for k a <= 3:\n{text}"


def test_monomial_basis_is_exact_for_a_polynomial_gap():
    """A quartic gap has a finite Taylor series: the monomial form agrees with Chebyshev for every a."""
    for a in HALF_WIDTHS:
        scene = scaled_scene(a, "quartic")
        ref = solve(scene, method="polynomial", order=30)
        for order in (6, 40):
            r = solve(scene, method="polynomial", order=order, basis="monomial")
            d = compare(r, ref)
            cond = r.info.get("cancellation_factor", math.nan)
            assert r.success and d <= 1e-10, f"quartic, a = {a:.0e}, order {order}: error {d:.1e} (cond {cond:.3e})"


@pytest.mark.parametrize("order", [200, 400])
def test_monomial_basis_at_very_high_order_fails_gracefully(order):
    """Beyond order 170 the monomial Taylor coefficients need (order)! > 1.8e308: report, never crash."""
    scene = scaled_scene(1e-2, "corrugated")
    try:
        with np.errstate(all="ignore"):
            r = solve(scene, method="polynomial", order=order, basis="monomial")
    except ValueError as exc:
        assert "order" in str(exc), f"a ValueError must name the order: {exc}"
        return
    d = compare(r, solve(scene, method="polynomial", order=60)) if r.success else math.inf
    assert not r.success or d <= 1e-6, f"order {order}: success=True with error {d:.2e}"


# ---------------------------------------------------------------------------------------------------------------
# validity detection
SPLIT = dict(radius=0.46, material=Material(210e9, 0.28), friction=0.3)


def sweep(wavelength, creep, n=24):
    """Solve the 20 um corrugation of docs/physics.md, Corrugated surface at ``n`` axis positions over one
    wavelength."""
    harmonic = Harmonic.from_wavelength(wavelength, 20e-6)
    out = []
    for xc in wavelength * np.arange(n) / n + 1e-4 * wavelength:
        scene = Scene(1e6, creep=creep, surface=Surface(harmonics=(harmonic,)), axis_position=float(xc), **SPLIT)
        out.append((scene, solve(scene, method="polynomial")))
    return out


@pytest.fixture(scope="module")
def split_sweeps():
    """Sweeps at 10 mm (splits), 15 mm (borderline) and 40 mm (valid) for two creeps."""
    return {(lam, creep): sweep(lam, creep) for lam in (0.010, 0.015, 0.040) for creep in (2e-4, -1e-3)}


def test_split_contact_is_solved_as_several_patches_or_reported(split_sweeps):
    """10 mm / 20 um splits the contact at some axis positions: there the result has several patches
    (rollcontact.multipatch) or, where that structure fails too, a message naming why."""
    for creep in (2e-4, -1e-3):
        results = split_sweeps[(0.010, creep)]
        several = [r for _, r in results if r.success and len(r.info.get("patches", ())) > 1]
        assert several, f"10 mm / 20 um must split the contact at some axis position (xi = {creep})"
        for _, r in results:
            if not r.success:
                assert any(w in r.message.lower() for w in ("split", "second contact patch", "more than one")), \
                    f"failure message must name the split: {r.message!r}"
    assert all(r.success and "patches" not in r.info for _, r in split_sweeps[(0.040, 2e-4)]), \
        "40 mm / 20 um: one patch everywhere"


@pytest.mark.parametrize("wavelength", [0.010, 0.015, 0.040])
def test_accepted_results_are_admissible(split_sweeps, wavelength):
    for creep in (2e-4, -1e-3):
        for scene, r in split_sweeps[(wavelength, creep)]:
            if not r.success:
                continue
            tag = f"lambda = {wavelength}, x_c = {scene.axis_position:.5f}, xi = {creep}"
            p_min, bound, slip_sign = field_violations(r, 0.3)
            assert p_min >= -1e-9, f"{tag}: accepted with p < 0 (min p/p0 = {p_min:.3e})"
            assert bound <= 0.0, f"{tag}: accepted with |q| > mu p by {bound:.3e} mu p0"
            assert slip_sign <= 1e-9, f"{tag}: accepted with slip against the creep ({slip_sign:.3e})"
            np.testing.assert_allclose(pressure_integral(r), 1e6, rtol=1e-9, err_msg=f"{tag}: int p dx = N'")


def test_gap_oracle_detects_a_second_contact():
    """Self-check of deformed_gap_minimum: a Hertz patch placed in a 10 mm / 20 um trough touches the crests."""
    hertz_result = solve(Scene(1e6, **SPLIT), method="closed_form")
    trough = Scene(1e6, surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 20e-6),)), axis_position=0.005,
                   **SPLIT)
    assert deformed_gap_minimum(hertz_result, trough, reach=0.01) < -1.0, "the oracle must see the crests touch"
    assert deformed_gap_minimum(hertz_result, Scene(1e6, **SPLIT), reach=0.01) >= -1e-9, "Hertz gap stays open"


@pytest.mark.parametrize("wavelength", [0.010, 0.015])
def test_accepted_results_keep_the_gap_open(split_sweeps, wavelength):
    reach = max(wavelength, math.sqrt(8 * 0.46 * 20e-6))
    for scene, r in split_sweeps[(wavelength, 2e-4)]:
        if r.success:
            g = deformed_gap_minimum(r, scene, reach)
            assert g >= -1e-9, f"x_c = {scene.axis_position:.5f}: accepted but the gap closes ({g:.3e} a^2/R)"


# ---------------------------------------------------------------------------------------------------------------
# options
@pytest.mark.parametrize("options, pattern", [
    (dict(basis="legendre"), "basis"),
    (dict(order=0), "order"),
    (dict(order=5000), "order"),
    (dict(order=2.5), "order"),
    (dict(tolerance=0.0), "tolerance"),
    (dict(tolerance=-1e-8), "tolerance"),
    (dict(tolerance=float("nan")), "tolerance"),
])
def test_bad_options_raise_value_error_naming_them(options, pattern):
    with pytest.raises(ValueError, match=pattern):
        solve(corrugated_scene(1.0, 0.2), method="polynomial", **options)


# ---------------------------------------------------------------------------------------------------------------
# fast paths: the previous implementation, caches, the shortcuts that replace checks by theorems
PREVIOUS_SCENES = {
    "corrugated 40 mm": Scene(1e6, creep=1e-3, axis_position=0.003,
                              surface=Surface(harmonics=(Harmonic.from_wavelength(0.04, 20e-6),))),
    "two harmonics": Scene(1e6, creep=-6e-4, axis_position=0.011,
                           surface=Surface(harmonics=(Harmonic.from_wavelength(0.04, 10e-6, 0.3),
                                                      Harmonic.from_wavelength(0.07, 8e-6, 1.1)))),
    "cubic+quartic": Scene(1e6, creep=5e-4, axis_position=0.001,
                           surface=Surface(polynomial=(0.0, 0.0, 0.0, 20.0, -2e4))),
    "full slip": Scene(1e6, creep=3e-3, axis_position=0.002,
                       surface=Surface(harmonics=(Harmonic.from_wavelength(0.04, 20e-6),))),
}
# (a, Delta, a*, T', p0, dT'/dxi) of the implementation before the speed-up (commit 640c1e1), default options
PREVIOUS_VALUES = {
    "corrugated 40 mm": (0.002063400091450822, -0.0005320467951720801, 0.0007929307995578276, 255141.72437529702,
                         308783461.6212997, 141906404.80852595),
    "two harmonics": (0.002321201428049882, -0.0009633243905912067, 0.0013484211203810851, -196771.3753344649,
                      274278446.1451541, 241319410.80844525),
    "cubic+quartic": (0.002109127259210186, -0.00014999248855371273, 0.0014952223650899507, 162376.47345164118,
                      294246969.0788317, 267591611.19424003),
    "full slip": (0.0020555468340162143, -0.0003588827013954296, 0.0, 300000.0, 309958676.3273164, 0.0),
}
FIELDS = ("contact_half_width", "contact_offset", "stick_half_width", "tangential_force_per_length", "max_pressure",
          "creep_stiffness_per_length")


@pytest.mark.parametrize("name", sorted(PREVIOUS_SCENES))
def test_results_equal_the_previous_implementation(name):
    """Same equations, fewer operations: every scalar output equal to round-off (1e-12)."""
    r = solve(PREVIOUS_SCENES[name], method="polynomial")
    assert r.success, r.message
    for field, before in zip(FIELDS, PREVIOUS_VALUES[name], strict=True):
        np.testing.assert_allclose(getattr(r, field), before, rtol=1e-12, atol=1e-15 * abs(PREVIOUS_VALUES[name][0]),
                                   err_msg=f"{name}: {field}")


def fingerprint(result):
    """Every number of a result, arrays as bytes: equal fingerprints mean bit-identical results."""
    info = tuple((k, v.tobytes() if isinstance(v, np.ndarray) else repr(v)) for k, v in sorted(result.info.items()))
    x = result.contact_offset + result.contact_half_width * np.linspace(-0.99, 0.99, 37)
    fields = (result.pressure(x).tobytes(), result.traction(x).tobytes(), np.nan_to_num(result.slip(x)).tobytes())
    return tuple(repr(getattr(result, f)) for f in FIELDS) + (result.message, result.iterations) + info + fields


def test_same_inputs_give_bit_identical_results_in_any_call_order():
    """The module-level caches (keyed by sizes) must not carry state from one call into another."""
    corrugated = PREVIOUS_SCENES["corrugated 40 mm"]
    falling = corrugated.replace(friction=ExponentialFalling(0.3, 0.4, 30.0), rolling_speed=20.0)
    calls = [(corrugated, {}), (corrugated, {"order": 7}), (corrugated, {"order": 40}),
             (PREVIOUS_SCENES["two harmonics"], {}), (PREVIOUS_SCENES["cubic+quartic"], {"basis": "monomial"}),
             (corrugated, {"check": False}), (falling, {}), (falling, {"nodes": 24}), (falling, {"nodes": 16})]
    first = [fingerprint(solve(s, method="polynomial", **o)) for s, o in calls]
    for cached in (chebyshev.unit_grid, chebyshev.theta_grid, chebyshev.pressure_table, chebyshev.orders,
                   chebyshev.surface_data, chebyshev.slope_tables, slip.slip_operators):
        cached.cache_clear()
    order = [8, 2, 6, 0, 4, 7, 1, 5, 3]
    again = {i: fingerprint(solve(calls[i][0], method="polynomial", **calls[i][1])) for i in order}
    for i, (_, options) in enumerate(calls):
        assert again[i] == first[i], f"call {i} ({options}) differs when made in another order"


@pytest.mark.parametrize("coefficients", [(3.5,), (-3.5,), (0.0, 1.0), (1e-300, -2e-4, 0.0, 3e2, -2e4),
                                          (0.1, 0.2, 0.3, -0.0, 7.0, 1e17, -3.3)])
def test_derivative_has_the_bits_of_numpys_polyder(coefficients):
    # slope_tables differentiates on lists (an FMU step re-expands the surface about a new axis every time); it must
    # give numpy's products, signed zeros included, or the results would move with the speed-up
    ours = chebyshev.derivative(coefficients)
    theirs = np.polynomial.polynomial.polyder(np.array(coefficients)).tolist()
    assert [repr(c) for c in ours] == [repr(c) for c in theirs], f"derivative {ours} != polyder {theirs}"


def test_cached_tables_are_read_only():
    tables = [chebyshev.unit_grid(11), *chebyshev.theta_grid(16, 5), *chebyshev.pressure_table(16, 5),
              *chebyshev.orders(5), *vars(slip.slip_operators(8)).values(),
              chebyshev.surface_data(PREVIOUS_SCENES["cubic+quartic"].surface)[1]]
    for table in tables:
        with pytest.raises(ValueError, match="read-only"):
            table[..., 0] = 1.0


@pytest.mark.parametrize("name", ["corrugated 40 mm", "two harmonics", "cubic+quartic"])
def test_monotone_creep_shortcut_finds_the_scanned_root(name, monkeypatch):
    """With Z'' < 1/R on the patch xi(a*) decreases, so Newton from the Carter guess must find the one root that
    the 9-point scan (taken when the curvature bound does not hold) brackets."""
    scene = PREVIOUS_SCENES[name]
    fast = solve(scene, method="polynomial")
    monkeypatch.setattr(chebyshev.SlopeExpansion, "curvature_bound", lambda self, lo, hi: math.inf)
    scanned = solve(scene, method="polynomial")
    assert fast.success and scanned.success, (fast.message, scanned.message)
    np.testing.assert_allclose(fast.stick_half_width, scanned.stick_half_width, rtol=1e-12, err_msg="a*")
    np.testing.assert_allclose(fast.tangential_force_per_length, scanned.tangential_force_per_length, rtol=1e-12,
                               err_msg="T'")


@pytest.mark.parametrize("ka, position", [(0.3, 0.23), (3.0, 0.61), (10.0, 0.0)])
def test_convex_gap_needs_no_sampling_and_sampling_agrees(ka, position, monkeypatch):
    """A convex gap with p >= 0 cannot close outside the patch: the sampled check, forced, must agree."""
    scene = corrugated_scene(ka, position)
    r = solve(scene, method="polynomial")
    e = chebyshev.SlopeExpansion(scene.radius, scene.axis_position, scene.surface)
    assert e.curvature_bound(-math.inf, math.inf) < 0.99 / scene.radius, "the test scene must be convex"
    x0 = r.contact_offset  # axis coordinates
    assert validity.outside_gap(r.distributions, e, r.contact_half_width, x0) is None
    monkeypatch.setattr(chebyshev.SlopeExpansion, "curvature_bound", lambda self, lo, hi: math.inf)
    assert validity.outside_gap(r.distributions, e, r.contact_half_width, x0) is None, \
        "sampling finds a closing gap where the convexity theorem says there is none"


@pytest.mark.parametrize("axis_position", [0.002, 0.005])
def test_closed_form_deformed_gap_equals_quadrature(axis_position):
    """deformed_gap (antiderivative of the outer transform) against the quadrature oracle, 10 mm / 20 um."""
    scene = Scene(1e6, creep=1e-3, axis_position=axis_position,
                  surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 20e-6),)), **SPLIT)
    r = solver.solve_polynomial(scene, order=30, check=False)  # the single patch, valid or not
    a, x0 = r.contact_half_width, r.contact_offset  # axis coordinates
    e = chebyshev.SlopeExpansion(scene.radius, scene.axis_position, scene.surface)
    estar = scene.material.contact_modulus
    theta = np.pi * np.arange(1, 801) / 801
    z = r.contact_offset + a * np.cos(theta)
    weights = a * np.pi / 801 * np.sin(theta) * r.pressure(z)  # Gauss-Chebyshev: int p g dz ~ sum weights g(z_i)
    for side, edge in ((1.0, r.trailing_edge), (-1.0, r.leading_edge)):
        # the slope of deformed_gap_minimum integrated by the trapezoidal rule on a cubically graded grid of 3000
        # points (gap ~ distance^1.5 at the edge), compared at every 100th
        x = edge + side * 0.01 * (np.arange(1, 3001) / 3000) ** 3
        slope = gap_slope(scene, x) - (2.0 / (math.pi * estar)) * (weights[None, :] / (x[:, None] - z[None, :])).sum(1)
        xs, ss = np.concatenate(([edge], x)), np.concatenate(([0.0], slope))
        oracle = np.cumsum(0.5 * (ss[1:] + ss[:-1]) * np.diff(xs))[99::100]
        closed = validity.deformed_gap(r.distributions, e, a, x0, (x[99::100] - r.contact_offset) / a)
        np.testing.assert_allclose(closed, oracle, rtol=1e-5, atol=1e-6 * a * a / scene.radius,
                                   err_msg=f"deformed gap, side {side:+.0f}")


@pytest.mark.parametrize("ka, position", [(1.0, 0.23), (3.0, 0.61), (10.0, 0.0)])
def test_max_pressure_is_the_maximum(ka, position):
    r = solve(corrugated_scene(ka, position), method="polynomial")
    x = interior_grid(r, 4001)
    i = int(np.argmax(r.pressure(x)))
    best = minimize_scalar(lambda v: -float(r.pressure(np.array([v]))[0]), bracket=(x[i - 1], x[i], x[i + 1]),
                           tol=1e-12)
    np.testing.assert_allclose(r.max_pressure, -best.fun, rtol=1e-13, err_msg="max p")
    assert r.max_pressure >= -best.fun * (1 - 1e-15), "the maximum must not be below a sampled value"


@pytest.mark.parametrize("tolerance", [1e-3, 1e-10, 1e-14])
def test_required_order_matches_its_definition(tolerance):
    """Smallest n >= max(poly degree, kh/2 + 1) with sum 2 k |Z| (kh/2)^n / n! <= tolerance h/R (by lgamma)."""
    for harmonics in ([(0.04, 20e-6)], [(0.04, 10e-6), (0.007, 1e-6), (0.15, 3e-5)]):
        surface = Surface(harmonics=tuple(Harmonic.from_wavelength(lam, amp, 0.2) for lam, amp in harmonics))
        e = chebyshev.SlopeExpansion(RADIUS, 0.0, surface)
        for h in (1e-5, 1e-3, 5e-3, 0.05):
            terms = [(0.5 * k * h, 2.0 * k * math.hypot(p, s)) for k, p, s in e.harmonic_list]
            n = max(1, int(max(z for z, _ in terms)) + 1)
            while n < 400 and sum(amp * math.exp(n * math.log(z) - math.lgamma(n + 1)) for z, amp in terms) > \
                    tolerance * h / RADIUS * (1 + 1e-12):
                n += 1
            assert abs(e.required_order(h, tolerance) - n) <= 1, f"h = {h}, {harmonics}"


def test_gap_slope_coefficients_are_jacobi_anger():
    """Against the Jacobi-Anger series written out with scipy.special.jv and cos(kc + n pi/2) per term (c in
    surface coordinates here, in axis coordinates for the expansion: the phase shift by k x_c is checked too)."""
    scene = PREVIOUS_SCENES["two harmonics"]
    e = chebyshev.SlopeExpansion(scene.radius, scene.axis_position, scene.surface)
    h, c, order = 2.3e-3, 0.0107, 25
    n = np.arange(order + 1)
    expected = np.zeros(order + 1)
    expected[0] = (c - scene.axis_position) / scene.radius
    expected[1] = h / scene.radius
    for hm in scene.surface.harmonics:
        k, phi, psi = hm.wavenumber, hm.cos_amplitude, hm.sin_amplitude
        ang = c * k + 0.5 * np.pi * n
        expected -= np.where(n == 0, 1.0, 2.0) * k * jv(n, k * h) * (psi * np.cos(ang) - phi * np.sin(ang))
    np.testing.assert_allclose(e.gap_slope_coefficients(h, c - scene.axis_position, order), expected, rtol=0,
                               atol=1e-14 * np.abs(expected).max())


def test_what_convexity_proves_the_sampled_checks_confirm(monkeypatch):
    """Where the curvature bound proves a check (validity_failures' docstring), the sampled check passes too.

    Random one- and two-harmonic surfaces (k a 0.1..20, curvature amplitude up to 1.2/R, some with cubic and
    quartic terms), creeps from 1e-3 to 2 times saturation, both signs; the sampled checks forced by setting the
    margins below any bound.
    """
    rng = np.random.default_rng(7)
    proven = {"traction bound": 0, "slip opposes": 0, "gap closes": 0}
    for _ in range(150):
        ka, curvature = 10 ** rng.uniform(-1, 1.3), rng.uniform(0.0, 1.2)
        freqs = rng.uniform(0.5, 2.0, rng.integers(1, 3))
        harmonics = tuple(Harmonic.from_wavelength(2 * math.pi * A_HERTZ / (ka * f),
                                                   curvature * (A_HERTZ / (ka * f)) ** 2 / (RADIUS * freqs.size),
                                                   rng.uniform(0, 2 * math.pi)) for f in freqs)
        polynomial_part = (0.0, 0.0, 0.0, rng.uniform(-30, 30), rng.uniform(-3e4, 0)) if rng.random() < 0.3 else ()
        scene = Scene(LOAD, creep=rng.choice([-1, 1]) * XI_SAT * 10 ** rng.uniform(-3, 0.3), radius=RADIUS,
                      material=MATERIAL, friction=MU, axis_position=rng.uniform(-0.02, 0.02),
                      surface=Surface(polynomial=polynomial_part, harmonics=harmonics))
        with monkeypatch.context() as patch:
            patch.setattr(solver, "CONVEX", -1.0)  # read by the creep root and by the checks
            patch.setattr(validity, "CONVEX", -1.0)
            patch.setattr(validity, "STICK_PROVEN", -1.0)
            sampled = solve(scene, method="polynomial")
        if not math.isfinite(sampled.contact_half_width):
            continue
        e = chebyshev.SlopeExpansion(RADIUS, scene.axis_position, scene.surface)
        x0, a = sampled.contact_offset, sampled.contact_half_width  # axis coordinates
        bound = e.curvature_bound(x0 - a, x0 + a) * RADIUS
        conditions = {"traction bound": bound <= validity.STICK_PROVEN and sampled.stick_half_width > 0,
                      "slip opposes": bound < validity.CONVEX,
                      "gap closes": e.curvature_bound(-math.inf, math.inf) * RADIUS < validity.CONVEX}
        for failure, holds in conditions.items():
            if holds:
                proven[failure] += 1
                assert failure not in sampled.message, f"proven, yet sampled: {sampled.message} (bound {bound:.3f}/R)"
    assert min(proven.values()) >= 20, f"too few scenes exercise each proof: {proven}"


# ---------------------------------------------------------------------------------------------------------------
# small creep: the slip width a - a* and the difference form from the zeros at a* = a
@pytest.mark.parametrize("sign", [1.0, -1.0])
@pytest.mark.parametrize("fraction", [1e-14, 1e-9, 5e-4, 2e-3])
def test_small_creep_force_is_carter_to_round_off(fraction, sign):
    """T' = mu N' u (2 - u), u = R |xi| / (mu a), to 1e-12 of itself at any creep: the difference form below
    w = 1e-3 a and the direct eqs 30-31 above it.  Regression: at 1e-14 saturation T' was 1 % off."""
    scene = Scene(LOAD, creep=sign * fraction * XI_SAT, radius=RADIUS, material=MATERIAL, friction=MU)
    r = solve(scene, method="polynomial")
    assert r.success, r.message
    np.testing.assert_allclose(r.tangential_force_per_length,
                               solve(scene, method="closed_form").tangential_force_per_length, rtol=1e-12,
                               err_msg=f"T' at xi = {fraction} saturation")


@pytest.mark.parametrize("scan", [False, True])
@pytest.mark.parametrize("name", ["corrugated 40 mm", "two harmonics", "cubic+quartic"])
def test_small_creep_force_is_linear_on_any_surface(name, scan, monkeypatch):
    """T'(xi) = k0 xi (1 + O(xi / xi_sat)) with k0 = dT'/dxi at xi = 0, both signs, at 1e-14 saturation to 1e-12;
    by Newton (convex patch) and by the 9-point scan (the curvature bound switched off)."""
    scene = PREVIOUS_SCENES[name]
    if scan:
        monkeypatch.setattr(chebyshev.SlopeExpansion, "curvature_bound", lambda self, lo, hi: math.inf)
    k0 = solve(scene.replace(creep=0.0), method="polynomial").creep_stiffness_per_length
    for xi in (1e-14 * XI_SAT, -1e-14 * XI_SAT):
        r = solve(scene.replace(creep=xi), method="polynomial")
        assert r.success, r.message
        np.testing.assert_allclose(r.tangential_force_per_length / xi, k0, rtol=1e-12, err_msg=f"T'/xi, xi = {xi}")


@pytest.mark.parametrize("name", ["corrugated 40 mm", "two harmonics", "cubic+quartic"])
def test_difference_form_equals_eqs_30_31_where_both_hold(name, monkeypatch):
    """At w = a - a* of 1-20 % of a both are exact to round-off: the difference form (the rates integrated from
    a* = a by the 5-point rule), forced there, must give eqs 30-31's a* and T'."""
    scene = PREVIOUS_SCENES[name]
    for fraction in (0.01, 0.2):
        s = scene.replace(creep=math.copysign(fraction * XI_SAT, scene.creep))
        direct = solve(s, method="polynomial")
        with monkeypatch.context() as patch:
            patch.setattr(solver, "DIFFERENCE_WIDTH", 1.0)
            difference = solve(s, method="polynomial")
        assert direct.success and difference.success, (direct.message, difference.message)
        w = (direct.contact_half_width - direct.stick_half_width) / direct.contact_half_width
        assert 5e-3 < w < 0.3, f"the test needs w/a in the range of both forms, got {w:.3g}"
        np.testing.assert_allclose(difference.tangential_force_per_length, direct.tangential_force_per_length,
                                   rtol=1e-12, err_msg=f"T' at w/a = {w:.3g}")
        np.testing.assert_allclose(difference.stick_half_width, direct.stick_half_width, rtol=1e-13,
                                   err_msg=f"a* at w/a = {w:.3g}")


def test_barely_falling_friction_is_solved_as_coulomb():
    """A law within COULOMB_REDUCTION of mu_s over the patch's slip velocities gives the Coulomb answer (said in
    info); one that falls by more over them goes through the slip iteration."""
    xi = 0.3 * XI_SAT
    coulomb = solve(Scene(LOAD, creep=xi, radius=RADIUS, material=MATERIAL, friction=MU), method="polynomial")
    flat = ExponentialFalling(MU, 0.5, 2e-11 / (xi + 2.0 * XI_SAT))  # falls by <= 1e-11 mu_s over V s < V (xi + 2 sat)
    r = solve(Scene(LOAD, creep=xi, radius=RADIUS, material=MATERIAL, friction=flat), method="polynomial")
    assert r.success and "coulomb_reduction" in r.info and "slip_iteration_history" not in r.info, r.info.keys()
    for field in FIELDS:
        assert getattr(r, field) == getattr(coulomb, field), field
    falling = ExponentialFalling(MU, 0.5, 2e-8 / xi)  # falls by ~1e-8 mu_s at V xi already
    r = solve(Scene(LOAD, creep=xi, radius=RADIUS, material=MATERIAL, friction=falling), method="polynomial")
    assert r.success and "coulomb_reduction" not in r.info and "slip_iteration_history" in r.info, r.info.keys()


# ---------------------------------------------------------------------------------------------------------------
# axis coordinates
def test_axis_a_kilometre_along_changes_nothing():
    """Regression: in surface coordinates a 48 nm patch 1 km along lost eps |x_c| / a ~ 5e-6 (T' 1e-9 mu N' off);
    relative to the axis a flat surface gives identical outputs wherever the axis stands."""
    here = Scene(1.0, creep=1e-14, radius=1e-3, material=Material(1e12, 0.3), friction=MU)
    reference = solve(here, method="polynomial")
    for axis_position in (1e3, -1e3, 0.7):
        there = solve(here.replace(axis_position=axis_position), method="polynomial")
        assert reference.success and there.success, (reference.message, there.message)
        for field in FIELDS:
            assert getattr(there, field) == getattr(reference, field), f"{field} at x_c = {axis_position}"


@pytest.mark.parametrize("name", ["corrugated 40 mm", "two harmonics", "cubic+quartic"])
def test_surface_moved_with_the_axis_gives_the_same_contact(name):
    """Z(X) -> Z(X - s) and x_c -> x_c + s leave the gap h0(X - x_c) as it was: harmonic phases and the polynomial
    re-expanded (numpy's composition here), to the rounding of the moved surface data."""
    scene = PREVIOUS_SCENES[name]
    shift = 0.05
    poly = np.polynomial.Polynomial(scene.surface.polynomial or (0.0,))(np.polynomial.Polynomial((-shift, 1.0)))
    harmonics = []
    for h in scene.surface.harmonics:  # Phi cos k(X - s) + Psi sin k(X - s)
        cs, sn = math.cos(h.wavenumber * shift), math.sin(h.wavenumber * shift)
        harmonics.append(Harmonic(h.wavenumber, h.cos_amplitude * cs - h.sin_amplitude * sn,
                                  h.sin_amplitude * cs + h.cos_amplitude * sn))
    moved = scene.replace(axis_position=scene.axis_position + shift,
                          surface=Surface(polynomial=tuple(poly.coef) if scene.surface.polynomial else (),
                                          harmonics=tuple(harmonics)))
    r, m = solve(scene, method="polynomial"), solve(moved, method="polynomial")
    assert r.success and m.success, (r.message, m.message)
    for field in FIELDS:
        np.testing.assert_allclose(getattr(m, field), getattr(r, field), rtol=1e-11, err_msg=field)


@pytest.mark.parametrize("size", [1, 2, 5, 9, 14])
def test_cached_power_to_chebyshev_matrix_equals_poly2cheb(size):
    """The cached conversion matrix of gap_slope_coefficients against numpy's poly2cheb, and it is frozen."""
    matrix = chebyshev.power_to_chebyshev(size)
    coefficients = np.random.default_rng(size).standard_normal(size)
    np.testing.assert_allclose(matrix @ coefficients, np.polynomial.chebyshev.poly2cheb(coefficients),
                               rtol=0.0, atol=1e-14 * np.abs(coefficients).sum())
    with pytest.raises(ValueError):
        matrix[0, 0] = 2.0


def test_surface_height_equals_surface_method_bit_for_bit():
    """deformed_gap's Horner evaluation of Z against Surface.height (numpy's polyval): the same operations, so the
    same bits, signed zeros included, for polynomials with zero and trailing-zero coefficients and harmonics."""
    rng = np.random.default_rng(11)
    for _ in range(200):
        poly = tuple((rng.standard_normal(rng.integers(0, 7)) * 10.0 ** rng.uniform(-3, 3)).tolist())
        if rng.random() < 0.3:
            poly = (0.0, 0.0, *poly, 0.0)
        harmonics = tuple(Harmonic(rng.uniform(1.0, 1e3), rng.standard_normal() * 1e-5, rng.standard_normal() * 1e-5)
                          for _ in range(rng.integers(0, 3)))
        surface = Surface(polynomial=poly, harmonics=harmonics)
        x = np.append(rng.standard_normal(40) * 10.0 ** rng.uniform(-4, 0), (0.0, -0.0))
        assert chebyshev.surface_height(surface, x).tobytes() == surface.height(x).tobytes(), (poly, harmonics)


def test_cached_outside_points_match_their_definition_and_are_read_only():
    """outside_gap's cached samples are outer_points of t = +-(1 + reach (i/m)^2), frozen; deformed_gap gives the
    same bits with them as from t alone."""
    t, *points = validity.outside_points(40, 2.5)
    u = 2.5 * (np.arange(1, 41) / 40.0) ** 2
    np.testing.assert_allclose(t, np.concatenate((1.0 + u, -1.0 - u)), rtol=1e-15)
    for computed, cached in zip(validity.outer_points(t), points, strict=True):
        assert computed.tobytes() == cached.tobytes()
    for table in (t, *points):
        with pytest.raises(ValueError, match="read-only"):
            table[0] = 0
    scene = Scene(1e6, creep=1e-3, axis_position=0.002,
                  surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 20e-6),)), **SPLIT)
    r = solve(scene, method="polynomial")
    e = chebyshev.SlopeExpansion(scene.radius, scene.axis_position, scene.surface)
    a, x0 = r.contact_half_width, r.contact_offset
    assert (validity.deformed_gap(r.distributions, e, a, x0, t, points).tobytes() ==
            validity.deformed_gap(r.distributions, e, a, x0, t).tobytes())


@pytest.mark.parametrize("closing", [2.0, 3.0, 4.14, 6.0, 10.0, 15.0, 20.0])
def test_a_gap_that_closes_far_outside_the_patch_is_never_a_silent_single_patch(closing):
    """A positive quartic ``Z = c4 X^4`` closes the undeformed gap ``X^2/2R - c4 X^4`` at ``|X| = d`` however far d
    lies (here 2a..20a, a the Hertz half-width) and keeps it closed beyond: the surface meets the cylinder there
    too, and the contact there grows without bound: no finite answer exists.  The polynomial method (one patch or
    several) and auto (the discretised fallback, whose window cannot hold it) must report failure."""
    a = 5e-3
    load = math.pi * E_STAR * a * a / (4 * RADIUS)
    c4 = 1.0 / (2.0 * RADIUS * (closing * a) ** 2)
    scene = Scene(load, creep=0.5 * MU * a / RADIUS, radius=RADIUS, material=MATERIAL, friction=rc.Coulomb(MU),
                  surface=Surface(polynomial=(0.0, 0.0, 0.0, 0.0, c4)))
    for method in ("polynomial", "auto"):
        result = solve(scene, method=method)
        assert not result.success, f"d = {closing} a, {method}: a converged answer ({result.message})"


def test_a_gap_that_closes_beyond_the_radius_is_no_concern():
    """Past |u| = R the parabola stands for no cylinder: a quartic closing there leaves the single patch valid."""
    a = 5e-3
    load = math.pi * E_STAR * a * a / (4 * RADIUS)
    c4 = 1.0 / (2.0 * RADIUS * (1.5 * RADIUS) ** 2)
    scene = Scene(load, creep=0.5 * MU * a / RADIUS, radius=RADIUS, material=MATERIAL, friction=rc.Coulomb(MU),
                  surface=Surface(polynomial=(0.0, 0.0, 0.0, 0.0, c4)))
    result = solve(scene, method="polynomial")
    assert result.success, result.message
