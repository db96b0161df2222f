"""Closed forms: Hertz, Carter/Fromm, Cattaneo, Mindlin-Deresiewicz, checked against independent quadrature.

Oracles are the integral equations themselves (docs/physics.md, Conventions), evaluated with scipy's QUADPACK:
``(2/(pi E*)) PV-int p(z)/(x - z) dz = h0'(x)`` in the patch, ``(2/(pi E*)) PV-int q(z)/(x - z) dz = -xi`` in the
stick zone, ``s = xi + (2/(pi E*)) PV-int q(z)/(x - z) dz`` in the slip zone, plus load/force balance.
Tolerances: identities and quadratures of smooth weights ~1e-12; principal values ~1e-9..1e-7; finite
differences 1e-6.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from quadrature import edge_quad, pressure_integral, pv_hilbert

from rollcontact import Material, Scene, Surface, carter, hertz, solve
from rollcontact.line.carter import cattaneo_traction, mindlin_unloading_traction

E_STAR = Material(210e9, 0.28).contact_modulus
RADIUS = 0.46
MU = 0.3
LOAD = 1.0e6


def carter_scene(creep, load=LOAD, tilt=0.0, mu=MU):
    """A Hertzian scene on the reference material, optionally on a surface tilted by ``Z = tilt X``.

    Parameters
    ----------
    creep : float
        xi.
    load : float
        N' [N/m].
    tilt : float
        alpha, surface slope.
    mu : float
        Coulomb coefficient.

    Returns
    -------
    Scene
    """
    return Scene(load, creep=creep, radius=RADIUS, material=Material(210e9, 0.28), friction=mu,
                 surface=Surface(polynomial=(0.0, tilt)))


def saturation_creep(load=LOAD, mu=MU):
    """``mu a / R``: the creep at which Carter's stick zone vanishes."""
    return mu * math.sqrt(4.0 * load * RADIUS / (math.pi * E_STAR)) / RADIUS


XI_SAT = saturation_creep()
CREEPS = [0.05 * XI_SAT, 0.4 * XI_SAT, 0.9 * XI_SAT, -0.3 * XI_SAT, -0.75 * XI_SAT]


# ---------------------------------------------------------------------------------------------------------------
# Hertz
@pytest.mark.parametrize("load", [1e3, 1e6, 5e7])
def test_hertz_half_width_and_peak_pressure(load):
    a, p0 = hertz(load, RADIUS, E_STAR)
    np.testing.assert_allclose(a, math.sqrt(4 * load * RADIUS / (math.pi * E_STAR)), rtol=1e-14,
                               err_msg="a = sqrt(4 N' R / (pi E*))")
    np.testing.assert_allclose(p0, 2 * load / (math.pi * a), rtol=1e-14, err_msg="p0 = 2 N'/(pi a)")


@pytest.mark.parametrize("load", [1e3, 1e6, 5e7])
@pytest.mark.parametrize("tilt", [0.0, 2e-3, -4e-3])
def test_pressure_balances_load(load, tilt):
    result = solve(carter_scene(0.3 * saturation_creep(load), load=load, tilt=tilt), method="closed_form")
    np.testing.assert_allclose(pressure_integral(result), load, rtol=1e-12,
                               err_msg=f"int p dx must equal N' = {load} (tilt {tilt})")


@pytest.mark.parametrize("tilt", [0.0, 2e-3, -4e-3])
def test_pressure_solves_normal_integral_equation(tilt):
    """(2/(pi E*)) PV-int p/(x - z) dz = h0'(x) = x/R - alpha inside the patch, by quadrature."""
    result = solve(carter_scene(0.0, tilt=tilt), method="closed_form")
    a = result.contact_half_width
    lo, hi = result.leading_edge, result.trailing_edge
    for x in result.contact_offset + a * np.cos(np.linspace(0.05, math.pi - 0.05, 9)):
        lhs = (2.0 / E_STAR) * pv_hilbert(result.pressure, [lo, hi], x)
        rhs = x / RADIUS - tilt
        assert abs(lhs - rhs) <= 1e-10 * a / RADIUS, \
            f"normal equation residual {lhs - rhs:.3e} at x = {x:.6g} m (a/R = {a / RADIUS:.3e}, tilt {tilt})"


def test_pressure_profile_is_elliptic():
    result = solve(carter_scene(0.0), method="closed_form")
    a, p0 = result.contact_half_width, result.max_pressure
    x = np.linspace(-1.2 * a, 1.2 * a, 241)
    # the factored root: 1 - (x/a)^2 cancels at x = a (grid point 220), its root is then 1.5e-9 p0 off
    want = np.where(np.abs(x) < a, p0 * np.sqrt(np.clip((a - x) * (a + x), 0, None)) / a, 0.0)
    np.testing.assert_allclose(result.pressure(x), want, rtol=0, atol=1e-12 * p0,
                               err_msg="p = p0 sqrt(1 - x^2/a^2) inside, 0 outside")


# ---------------------------------------------------------------------------------------------------------------
# Carter: forces
@pytest.mark.parametrize("creep", CREEPS + [1.5 * XI_SAT, -2.0 * XI_SAT])
def test_traction_integrates_to_tangential_force(creep):
    result = solve(carter_scene(creep), method="closed_form")
    lead = result.leading_edge
    stick_end = lead + 2.0 * result.stick_half_width
    total = edge_quad(result.traction, [lead, stick_end, result.trailing_edge])
    t = result.tangential_force_per_length
    np.testing.assert_allclose(total, t, rtol=1e-10, atol=1e-12 * MU * LOAD,
                               err_msg=f"int q dx must equal T' at xi = {creep:.3e}")


@pytest.mark.parametrize("creep", CREEPS)
def test_carter_force_formula(creep):
    a = math.sqrt(4 * LOAD * RADIUS / (math.pi * E_STAR))
    a_star = a - RADIUS * abs(creep) / MU
    t, stick, _ = carter(LOAD, creep, RADIUS, E_STAR, MU)
    np.testing.assert_allclose(stick, a_star, rtol=1e-13, err_msg="a* = a - R |xi| / mu (eq 17)")
    np.testing.assert_allclose(t, math.copysign(MU * LOAD * (1 - (a_star / a) ** 2), creep), rtol=1e-13,
                               err_msg="T' = mu N' (1 - (a*/a)^2) sign(xi)")


def test_creep_curve_is_odd_monotone_bounded_and_saturates():
    xis = np.linspace(-2.5 * XI_SAT, 2.5 * XI_SAT, 201)
    ts = np.array([solve(carter_scene(xi), method="closed_form").tangential_force_per_length for xi in xis])
    mu_n = MU * LOAD
    assert np.all(np.abs(ts) <= mu_n * (1 + 1e-15)), f"|T'| exceeds mu N': max {np.max(np.abs(ts)) / mu_n}"
    np.testing.assert_allclose(ts, -ts[::-1], rtol=0, atol=1e-12 * mu_n, err_msg="T'(xi) must be odd")
    assert np.all(np.diff(ts) >= 0.0), "T'(xi) must be non-decreasing"
    inside = np.abs(xis) < XI_SAT * (1 - 1e-9)
    assert np.all(np.diff(ts[inside]) > 0.0), "T'(xi) must increase strictly below saturation"
    beyond = np.abs(xis) >= XI_SAT
    assert beyond.sum() > 50, "test grid must reach beyond saturation"
    np.testing.assert_array_equal(ts[beyond], np.sign(xis[beyond]) * mu_n,
                                  err_msg="beyond |xi| = mu a / R the force is exactly mu N' sign(xi)")
    t_sat = solve(carter_scene(XI_SAT), method="closed_form")
    np.testing.assert_allclose(t_sat.tangential_force_per_length, mu_n, rtol=1e-12,
                               err_msg="T' reaches mu N' at xi = mu a / R")


def test_initial_slope_is_pi_estar_a_over_two():
    a = math.sqrt(4 * LOAD * RADIUS / (math.pi * E_STAR))
    h = 1e-7 * XI_SAT
    fd = (solve(carter_scene(h), method="closed_form").tangential_force_per_length
          - solve(carter_scene(-h), method="closed_form").tangential_force_per_length) / (2 * h)
    np.testing.assert_allclose(fd, math.pi * E_STAR * a / 2, rtol=1e-6,
                               err_msg="dT'/dxi at xi = 0 must be pi E* a / 2")
    np.testing.assert_allclose(solve(carter_scene(0.0), method="closed_form").creep_stiffness_per_length,
                               math.pi * E_STAR * a / 2, rtol=1e-13, err_msg="creep_stiffness_per_length at 0")


@pytest.mark.parametrize("creep", CREEPS + [1.2 * XI_SAT])
def test_creep_stiffness_equals_finite_difference(creep):
    h = 1e-6 * XI_SAT
    fd = (solve(carter_scene(creep + h), method="closed_form").tangential_force_per_length
          - solve(carter_scene(creep - h), method="closed_form").tangential_force_per_length) / (2 * h)
    k = solve(carter_scene(creep), method="closed_form").creep_stiffness_per_length
    np.testing.assert_allclose(k, fd, rtol=1e-6, atol=1e-9 * math.pi * E_STAR * 2.27e-3,
                               err_msg=f"creep_stiffness_per_length vs central difference at xi = {creep:.3e}")


# ---------------------------------------------------------------------------------------------------------------
# Carter: fields
@pytest.mark.parametrize("creep", CREEPS + [1.5 * XI_SAT, -1.5 * XI_SAT])
def test_traction_bounded_by_friction_and_equal_to_mu_p_in_slip(creep):
    result = solve(carter_scene(creep), method="closed_form")
    a, p0 = result.contact_half_width, result.max_pressure
    x = np.linspace(-1.1 * a, 1.1 * a, 4001)
    p, q = result.pressure(x), result.traction(x)
    excess = np.abs(q) - MU * p
    assert np.all(excess <= 1e-12 * MU * p0), f"|q| > mu p by {excess.max() / (MU * p0):.3e} mu p0"
    slip_zone = x > result.leading_edge + 2 * result.stick_half_width
    np.testing.assert_allclose(q[slip_zone], MU * p[slip_zone] * np.sign(creep), rtol=0, atol=1e-12 * MU * p0,
                               err_msg="q = mu p sign(xi) in the slip zone")
    stick = (x > result.leading_edge) & (x < result.leading_edge + 2 * result.stick_half_width)
    if result.stick_half_width > 0:
        assert np.all(np.abs(q[stick]) < MU * p[stick]), "|q| < mu p strictly inside the stick zone"
        assert np.all(q[stick] * creep > 0), "q has the sign of the creep inside the stick zone"
    assert np.all(q[np.abs(x) > a] == 0.0), "q = 0 outside the patch"


@pytest.mark.parametrize("creep", [0.4 * XI_SAT, -0.6 * XI_SAT])
def test_traction_is_continuous(creep):
    """The max jump between neighbours shrinks like sqrt(h) on refinement (a jump would not shrink)."""
    result = solve(carter_scene(creep), method="closed_form")
    a, p0 = result.contact_half_width, result.max_pressure
    jumps = []
    for n in (1_001, 10_001, 100_001):
        q = result.traction(np.linspace(-1.05 * a, 1.05 * a, n))
        jumps.append(float(np.max(np.abs(np.diff(q)))) / (MU * p0))
    assert jumps[1] < jumps[0] / 2 and jumps[2] < jumps[1] / 2, f"max jumps do not shrink: {jumps}"
    assert jumps[2] < 2e-2, f"max jump {jumps[2]:.3e} mu p0 on the finest grid"


@pytest.mark.parametrize("creep", CREEPS)
def test_slip_zero_in_stick_and_eq16_in_slip(creep):
    result = solve(carter_scene(creep), method="closed_form")
    a, a_star = result.contact_half_width, result.stick_half_width
    np.testing.assert_allclose(a_star, a - RADIUS * abs(creep) / MU, rtol=1e-13, err_msg="a* (eq 17)")
    x = np.linspace(-a, a, 2001)[1:-1]
    s = result.slip(x)
    stick = x < -a + 2 * a_star
    np.testing.assert_array_equal(s[stick], 0.0, err_msg="s = 0 in the stick zone at the leading edge")
    x_star = x[~stick] + a - a_star
    want = math.copysign(1.0, creep) * (MU / RADIUS) * np.sqrt(x_star**2 - a_star**2)
    np.testing.assert_allclose(s[~stick], want, rtol=1e-12, atol=1e-12 * abs(creep),
                               err_msg="slip must follow eq 16 s = (mu/R) sqrt(x*^2 - a*^2) sign(xi)")
    assert np.all(s[~stick][1:] * creep > 0), "slip has the sign of the creep in the slip zone"
    assert np.all(np.isnan(result.slip(np.array([-1.5 * a, 1.5 * a])))), "slip is NaN outside the patch"


@pytest.mark.parametrize("creep", [0.2 * XI_SAT, 0.7 * XI_SAT, -0.5 * XI_SAT])
def test_carter_stick_condition_by_quadrature(creep):
    """(2/(pi E*)) PV-int q(z)/(x - z) dz = -xi inside the stick zone (independent of Carter's algebra)."""
    result = solve(carter_scene(creep), method="closed_form")
    lead, a_star = result.leading_edge, result.stick_half_width
    pieces = [lead, lead + 2 * a_star, result.trailing_edge]
    for x in lead + a_star * (1.0 + np.cos(np.linspace(0.1, math.pi - 0.1, 7))):
        lhs = (2.0 / E_STAR) * pv_hilbert(result.traction, pieces, x)
        assert abs(lhs + creep) <= 1e-7 * abs(creep), \
            f"stick condition violated at x = {x:.6g}: du/dx = {lhs:.9e}, -xi = {-creep:.9e}"


@pytest.mark.parametrize("creep", [0.2 * XI_SAT, -0.7 * XI_SAT, 1.3 * XI_SAT])
def test_slip_equals_creep_plus_displacement_gradient_by_quadrature(creep):
    """s = xi + (2/(pi E*)) PV-int q/(x - z) dz in the slip zone, computed from result.traction alone."""
    result = solve(carter_scene(creep), method="closed_form")
    a = result.contact_half_width
    lo, hi = result.leading_edge, result.trailing_edge
    slip_start = lo + 2 * result.stick_half_width
    for x in slip_start + (hi - slip_start) * np.array([0.05, 0.3, 0.6, 0.95]):
        s = creep + (2.0 / E_STAR) * pv_hilbert(result.traction, [lo, slip_start, hi], x)
        got = float(result.slip(np.array([x]))[0])
        assert abs(got - s) <= 1e-7 * MU * a / RADIUS, f"slip at x = {x:.6g}: result {got:.9e}, quadrature {s:.9e}"


def test_opposite_creep_mirrors_traction_and_force():
    plus = solve(carter_scene(0.45 * XI_SAT), method="closed_form")
    minus = solve(carter_scene(-0.45 * XI_SAT), method="closed_form")
    a = plus.contact_half_width
    x = np.linspace(-a, a, 501)
    np.testing.assert_allclose(minus.traction(x), -plus.traction(x), rtol=0, atol=1e-12 * plus.max_pressure,
                               err_msg="q(-xi) = -q(xi): the stick zone stays at the leading edge")
    np.testing.assert_allclose(minus.tangential_force_per_length, -plus.tangential_force_per_length, rtol=1e-15,
                               err_msg="T'(-xi) = -T'(xi)")
    assert minus.stick_half_width == plus.stick_half_width, "a* depends on |xi| only"


def test_zero_load_gives_zero_everything():
    result = solve(carter_scene(1e-3, load=0.0), method="closed_form")
    assert result.success, f"N' = 0 must succeed: {result.message}"
    for name in ("tangential_force_per_length", "contact_half_width", "stick_half_width", "max_pressure",
                 "traction_coefficient"):
        assert getattr(result, name) == 0.0, f"{name} = {getattr(result, name)} at N' = 0"
    x = np.linspace(-1e-3, 1e-3, 11)
    assert np.all(result.pressure(x) == 0.0) and np.all(result.traction(x) == 0.0), "fields must vanish at N' = 0"
    assert carter(0.0, 1e-3, RADIUS, E_STAR, MU) == (0.0, 0.0, 0.0), "carter() at N' = 0"


@pytest.mark.parametrize("tilt", [1e-3, -3e-3])
def test_tilt_moves_contact_uphill_by_r_alpha_and_keeps_forces(tilt):
    creep = 0.5 * XI_SAT
    flat = solve(carter_scene(creep), method="closed_form")
    tilted = solve(carter_scene(creep, tilt=tilt), method="closed_form")
    np.testing.assert_allclose(tilted.contact_offset, RADIUS * tilt, rtol=1e-14,
                               err_msg="Z = alpha X moves the contact by R alpha (uphill)")
    for name in ("tangential_force_per_length", "contact_half_width", "stick_half_width", "max_pressure"):
        np.testing.assert_allclose(getattr(tilted, name), getattr(flat, name), rtol=1e-14,
                                   err_msg=f"{name} must not change on a tilted surface")
    x = np.linspace(-1.2, 1.2, 241) * flat.contact_half_width
    np.testing.assert_allclose(tilted.traction(x + RADIUS * tilt), flat.traction(x), rtol=0,
                               atol=1e-10 * flat.max_pressure, err_msg="q is translated by R alpha")
    # uphill: the surface rises towards +x for alpha > 0, so the patch centre lies where Z is higher
    assert tilted.contact_offset * tilt > 0, "the patch moves uphill"


# ---------------------------------------------------------------------------------------------------------------
# Cattaneo and Mindlin-Deresiewicz
@pytest.mark.parametrize("force_ratio", [0.0, 0.2, 0.6, 0.95, 1.0])
def test_cattaneo_force_bound_and_stick_condition(force_ratio):
    a, p0 = hertz(LOAD, RADIUS, E_STAR)
    c = a * math.sqrt(1 - force_ratio)

    def q(x):
        return cattaneo_traction(x, a, p0, MU, force_ratio)

    total = edge_quad(q, [-a, -c, c, a] if c > 0 else [-a, a])
    np.testing.assert_allclose(total, force_ratio * MU * LOAD, rtol=1e-10, atol=1e-12 * MU * LOAD,
                               err_msg=f"int q = Q' = {force_ratio} mu N'")
    x = np.linspace(-a, a, 2001)
    p = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    assert np.all(np.abs(q(x)) <= MU * p * (1 + 1e-12) + 1e-12 * MU * p0), "|q| <= mu p"
    slip = np.abs(x) > c
    np.testing.assert_allclose(q(x)[slip], MU * p[slip], rtol=0, atol=1e-12 * MU * p0,
                               err_msg="q = mu p in the slip annulus c < |x| < a")
    for x0 in c * np.array([-0.8, -0.3, 0.1, 0.7]) if c > 0 else []:
        du = (2.0 / E_STAR) * pv_hilbert(q, [-a, -c, c, a], x0)
        assert abs(du) <= 1e-8 * MU * a / RADIUS, f"rigid stick zone: du/dx = {du:.3e} at x = {x0:.4g}"


@pytest.mark.parametrize("peak_ratio, force_ratio", [(0.8, 0.5), (0.8, -0.8), (0.5, 0.0), (1.0, 0.3)])
def test_mindlin_unloading_force_bound_and_stick_condition(peak_ratio, force_ratio):
    a, p0 = hertz(LOAD, RADIUS, E_STAR)
    b = a * math.sqrt(1 - 0.5 * (peak_ratio - force_ratio))

    def q(x):
        return mindlin_unloading_traction(x, a, p0, MU, peak_ratio, force_ratio)

    c = a * math.sqrt(1 - peak_ratio)
    points = sorted({-a, -b, -c, c, b, a})
    total = edge_quad(q, points)
    np.testing.assert_allclose(total, force_ratio * MU * LOAD, rtol=1e-10, atol=1e-12 * MU * LOAD,
                               err_msg=f"unloading from {peak_ratio} to {force_ratio} mu N': int q = Q'")
    x = np.linspace(-a, a, 2001)
    p = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    assert np.all(np.abs(q(x)) <= MU * p * (1 + 1e-12) + 1e-12 * MU * p0), "|q| <= mu p"
    reverse = np.abs(x) > b
    np.testing.assert_allclose(q(x)[reverse], -MU * p[reverse], rtol=0, atol=1e-12 * MU * p0,
                               err_msg="reversed slip q = -mu p in b < |x| < a")

    # stick during unloading: the displacement change from the peak state is rigid in |x| < b
    def dq(z):
        return q(z) - cattaneo_traction(z, a, p0, MU, peak_ratio)

    for x0 in b * np.array([-0.9, -0.2, 0.4, 0.85]):
        du = (2.0 / E_STAR) * pv_hilbert(dq, points, x0)
        assert abs(du) <= 1e-8 * MU * a / RADIUS, f"stick while unloading: d(du/dx) = {du:.3e} at x = {x0:.4g}"


def test_mindlin_at_peak_equals_cattaneo():
    a, p0 = hertz(LOAD, RADIUS, E_STAR)
    x = np.linspace(-1.1 * a, 1.1 * a, 301)
    np.testing.assert_allclose(mindlin_unloading_traction(x, a, p0, MU, 0.7, 0.7), cattaneo_traction(x, a, p0, MU, 0.7),
                               rtol=0, atol=1e-12 * p0, err_msg="unloading by zero must leave the Cattaneo state")
