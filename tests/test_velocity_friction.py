"""Velocity-dependent friction by the polynomial method (paper section 4.2; physics.md section 5)."""

import numpy as np
import pytest

import rollcontact as rc
from rollcontact.velocity_friction import solve_velocity_dependent

LOAD = 1e6  # N/m
V = 20.0  # m/s
FALLING = rc.ExponentialFalling(mu_static=0.3, kinetic_ratio=0.4, decay=0.6)


def scene(creep, friction=FALLING, **kw):
    return rc.Scene(normal_load_per_length=LOAD, creep=creep, friction=friction, rolling_speed=V, **kw)


def carter_inputs():
    ref = rc.solve(scene(1e-3, rc.Coulomb(0.3)), method="closed_form")
    pol = rc.solve(scene(1e-3, rc.Coulomb(0.3)), method="polynomial")
    return ref, pol.info["pressure_coefficients"]


@pytest.mark.parametrize("creep", [2e-4, 1e-3, -1e-3, 1.4e-3, 5e-3])
def test_coulomb_law_through_the_slip_iteration_is_carter(creep):
    ref = rc.solve(scene(creep, rc.Coulomb(0.3)), method="closed_form")
    _, c_n = carter_inputs()
    out = solve_velocity_dependent(c_n, ref.contact_half_width, 0.0, rc.Material().contact_modulus,
                                   rc.Coulomb(0.3), V, creep, nodes=96)
    assert out["converged"], out["message"]
    np.testing.assert_allclose(out["tangential_force_per_length"], ref.tangential_force_per_length, rtol=1e-11,
                               atol=1e-9 * LOAD, err_msg="T' of the slip iteration with constant mu vs Carter")
    np.testing.assert_allclose(out["stick_half_width"], ref.stick_half_width, rtol=1e-10, atol=1e-14,
                               err_msg="a* vs Carter")
    x = np.linspace(-0.999, 0.999, 301) * ref.contact_half_width
    np.testing.assert_allclose(out["distributions"].traction(x), ref.traction(x), atol=1e-10 * ref.max_pressure,
                               err_msg="q(x) vs Carter")


def test_falling_friction_creep_curve_has_a_maximum_and_decays():
    creeps = np.array([2e-4, 5e-4, 1e-3, 1.5e-3, 2e-3, 3e-3, 5e-3, 1e-2, 2e-2, 5e-2])
    results = [rc.solve(scene(float(c))) for c in creeps]
    assert all(r.method == "polynomial" and r.success for r in results), [r.message for r in results]
    mu_t = np.array([r.traction_coefficient for r in results])
    i = int(np.argmax(mu_t))
    assert 0 < i < len(creeps) - 1, f"the creep curve must peak inside the sweep, T'/N' = {mu_t}"
    assert np.all(np.diff(mu_t[: i + 1]) > 0) and np.all(np.diff(mu_t[i:]) < 0), f"rise then fall: {mu_t}"
    assert mu_t.max() < FALLING.mu_static, "T' <= mu_s N'"
    # far in full slip the traction tends to mu(V xi) N' (slip nearly uniform)
    r = results[-1]
    assert abs(r.traction_coefficient - float(FALLING.coefficient(V * creeps[-1]))) < 0.02, r.traction_coefficient


def test_odd_in_creep():
    r_pos = rc.solve(scene(1e-3))
    r_neg = rc.solve(scene(-1e-3))
    np.testing.assert_allclose(r_neg.tangential_force_per_length, -r_pos.tangential_force_per_length, rtol=1e-12,
                               err_msg="T'(-xi) = -T'(xi)")


def test_traction_bounds_and_slip_direction():
    r = rc.solve(scene(1e-3))
    a = r.contact_half_width
    x = np.linspace(-0.995, 0.995, 801) * a
    q, p, s = r.traction(x), r.pressure(x), r.slip(x)
    mu = FALLING.coefficient(V * np.abs(np.nan_to_num(s)))
    assert np.all(np.abs(q) <= mu * p * (1 + 1e-3) + 1e-6 * r.max_pressure), "|q| <= mu(V|s|) p"
    slip_zone = x > r.leading_edge + 2 * r.stick_half_width + 0.02 * a
    assert np.all(s[slip_zone] > 0), "slip has the sign of the creep behind the stick zone"
    np.testing.assert_allclose(q[slip_zone], (mu * p)[slip_zone], rtol=2e-3, atol=2e-4 * r.max_pressure,
                               err_msg="q = mu(V s) p in the slip zone")


def test_spike_at_the_stick_slip_boundary():
    """Paper Figure 5: with falling friction q/p peaks at the stick/slip boundary, above its trailing values."""
    steep = rc.ExponentialFalling(mu_static=0.3, kinetic_ratio=0.4, decay=30.0)
    r = rc.solve(scene(5e-4, steep))
    assert r.success, r.message
    a = r.contact_half_width
    xb = r.leading_edge + 2 * r.stick_half_width
    x = np.linspace(r.leading_edge + 0.01 * a, r.trailing_edge - 0.01 * a, 2001)
    ratio = r.traction(x) / r.pressure(x)
    ib = int(np.argmax(ratio))
    assert abs(x[ib] - xb) < 0.05 * a, f"q/p peaks at the boundary x = {xb:.4g}, found {x[ib]:.4g}"
    assert ratio[ib] > ratio[-1] + 0.05, f"q/p falls behind the boundary: {ratio[ib]:.3f} -> {ratio[-1]:.3f}"


def test_convergence_in_nodes():
    t = [rc.solve(scene(1e-3), nodes=n).tangential_force_per_length for n in (48, 96, 192, 384)]
    d = np.abs(np.diff(t))
    assert d[-1] < 1e-4 * abs(t[-1]), f"T' converged to 1e-4 at 384 nodes: {t}"
    assert d[-1] < d[0], f"differences shrink with the number of nodes: {d}"


def test_corrugated_surface_with_falling_friction_reduces_with_flat_surface():
    flat = rc.solve(scene(1e-3))
    tiny = rc.solve(scene(1e-3, surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.04, 1e-12),))))
    np.testing.assert_allclose(tiny.tangential_force_per_length, flat.tangential_force_per_length, rtol=1e-6,
                               err_msg="a vanishing corrugation leaves the falling-friction solution unchanged")
