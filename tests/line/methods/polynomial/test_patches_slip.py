"""Velocity-dependent friction on a contact of several patches (rollcontact.split_friction).

Oracles: the Coulomb limit (a law that cannot tell itself from Coulomb's: the several-patch solution of
rollcontact.multipatch, tested against QUADPACK in tests/test_multipatch.py), the discretised slip iteration on both
patches, the discrete equations themselves at the patch nodes, the solution on four times the nodes, and symmetry.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact import Coulomb, ExponentialFalling, Harmonic, Scene, Surface, solve
from rollcontact.line.methods.polynomial import patches
from rollcontact.line.methods.polynomial.chebyshev import SlopeExpansion
from rollcontact.line.methods.polynomial.patches_slip import SplitVelocityDistributions, solve_split_velocity

LOAD = 1e6
RADIUS = 0.46
SPEED = 20.0
LAW = ExponentialFalling(0.3, 0.4, 3.0)  # mu_s = 0.3, falling to 0.12 over ~1/3 m/s
STEEP = ExponentialFalling(0.3, 0.4, 30.0)


def corrugated(wavelength=0.010, axis_position=0.0045, creep=1e-3, friction=LAW, **extra):
    """Steel cylinder (R = 0.46 m) on a 20 um corrugation; by default the two-patch scene of docs/physics.md,
    Corrugated surface."""
    return Scene(LOAD, creep=creep, axis_position=axis_position, friction=friction, rolling_speed=SPEED,
                 surface=Surface(harmonics=(Harmonic.from_wavelength(wavelength, 20e-6),)), **extra)


SCENE = corrugated()
ESTAR = SCENE.material.contact_modulus
A_REF = math.sqrt(4 * LOAD * RADIUS / (math.pi * ESTAR))
XI_SAT = 0.3 * A_REF / RADIUS


def split_solve(scene, nodes=16, friction=None):
    """:func:`solve_split_velocity` on the scene's patches (normal problem to 1e-12)."""
    expansion = SlopeExpansion(scene.radius, scene.axis_position, scene.surface)
    start = patches.patch_starts(scene, None)[0]
    normal = patches.split_normal(expansion, LOAD, ESTAR, start, 1e-12, None)
    assert not normal.failure, normal.failure
    return solve_split_velocity(expansion, normal, ESTAR, friction or scene.friction, SPEED, scene.creep, nodes)


def assert_agrees_with_the_discretised(r, scene, elements):
    """T' of ``r`` within the discretised slip iteration's error estimate on ``elements``, and every stick zone of
    ``r`` (but those of patches that slip throughout) within two elements of the discretised sticking elements (p > 0,
    s = 0) about it: the discretised certificate checks the traction bound and the slip direction on every element
    and assumes no structure of the zones."""
    d = solve(scene, method="discretised", elements=elements)
    assert d.success, d.message
    assert abs(d.tangential_force_per_length / r.tangential_force_per_length - 1.0) <= d.info["error_estimate"]
    dist = d.distributions
    element = dist.x[1] - dist.x[0]
    for lo, hi in r.info["stick_zones"]:
        if hi == lo:
            continue
        sticking = dist.x[(dist.p > 0.0) & (dist.s == 0.0) & (dist.x > lo - 0.5 * A_REF) & (dist.x < hi + 0.5 * A_REF)]
        assert abs(sticking.min() - lo) <= 2 * element and abs(sticking.max() - hi) <= 2 * element, \
            (sticking.min(), sticking.max(), lo, hi)


@pytest.fixture(scope="module")
def solved():
    """The split scene with the falling law at three creeps (of the Carter saturation creep)."""
    return {ratio: split_solve(SCENE.replace(creep=ratio * XI_SAT)) for ratio in (0.1, 0.5, 0.9)}


@pytest.mark.parametrize("ratio", [0.1, 0.5, 0.9, 2.0])
def test_coulomb_limit_is_the_several_patch_coulomb_solution(ratio):
    """A law whose mu changes by ~1e-12 over the slip velocities is Coulomb's: T', the stick zones and the
    traction equal rollcontact.multipatch's Coulomb solution (exact in T' at every order) to the slip iteration's
    tolerance."""
    scene = SCENE.replace(creep=ratio * XI_SAT)
    flat = split_solve(scene, friction=ExponentialFalling(0.3, 0.4, 1e-12))
    coulomb = solve(scene.replace(friction=Coulomb(0.3)), method="polynomial")
    assert flat.success and coulomb.success and len(coulomb.info["patches"]) == 2, (flat.message, coulomb.message)
    assert flat.tangential_force_per_length == pytest.approx(coulomb.tangential_force_per_length, rel=1e-8), \
        "T' of a flat law against the Coulomb several-patch solution"
    for (lo, hi), (clo, chi) in zip(flat.info["stick_zones"], coulomb.info["stick_zones"], strict=True):
        assert abs(hi - chi) <= 1e-8 * A_REF and abs(lo - clo) <= 1e-12 * A_REF, "stick zones"
    x = np.linspace(-A_REF, A_REF, 401)
    q, qc = flat.distributions.traction(x), coulomb.distributions.traction(x)
    assert np.abs(q - qc).max() <= 1e-6 * 0.3 * coulomb.max_pressure, "traction against the Coulomb solution"


def test_split_scene_with_a_falling_law_is_solved_on_two_patches(solved):
    for ratio, r in solved.items():
        assert r.success and len(r.info["patches"]) == 2, (ratio, r.message)
        assert isinstance(r.distributions, SplitVelocityDistributions)
        assert 0.0 < r.tangential_force_per_length < 0.3 * LOAD, "0 < T' < mu_s N'"


def test_discrete_equations_hold_at_the_patch_nodes(solved):
    """At the nodes of every patch behind its stick zone ``q = mu(V s) p`` with the slip of the returned fields, and
    the slip has the creep's sign; in the stick zones ``|q| <= mu_s p``."""
    for r in solved.values():
        dist = r.distributions
        nodes = r.info["nodes"]
        theta = np.pi * (np.arange(nodes) + 0.5) / nodes
        for (c, h), (zc, zh) in zip(dist.patches, dist.zones, strict=True):
            x = c + h * np.cos(theta)
            behind = x > zc + zh
            s, q, p = dist.slip(x[behind]), dist.traction(x[behind]), dist.pressure(x[behind])
            assert (s >= 0.0).all(), "slip with the creep behind the stick zone"
            assert np.abs(q - LAW.coefficient(SPEED * s) * p).max() <= 1e-8 * 0.3 * r.max_pressure, \
                "q = mu(V s) p at the slipping nodes"
            if zh == 0.0:  # the patch slips throughout
                continue
            inside = np.linspace(zc - zh, zc + zh, 101)[1:-1]
            assert (np.abs(dist.traction(inside)) <= 0.3 * dist.pressure(inside) + 1e-9 * r.max_pressure).all(), \
                "|q| <= mu_s p in the stick zone"
            assert np.abs(dist.slip(inside)).max() == 0.0, "no slip in the stick zone"


def test_agrees_with_the_discretised_slip_iteration_on_both_patches():
    """The discretised slip iteration (a stick zone at each patch's leading edge, tests/test_discretised.py)
    converges to the polynomial T': its distance falls with n and stays within the discretised error estimate."""
    r = split_solve(SCENE.replace(creep=0.5 * XI_SAT))
    distances = []
    for n in (200, 800):
        d = solve(SCENE.replace(creep=0.5 * XI_SAT), method="discretised", elements=n)
        assert d.success and len(d.info["patches"]) == 2, d.message
        distance = abs(d.tangential_force_per_length / r.tangential_force_per_length - 1.0)
        assert distance <= d.info["error_estimate"], f"n = {n}: distance {distance:.3g} beyond the estimate"
        distances.append(distance)
    assert distances[1] < distances[0], f"no convergence towards the polynomial T': {distances}"


def test_velocity_dependent_part_agrees_with_the_discretised_difference():
    """T'(falling law) - T'(Coulomb) on the same grid cancels most of the discretised error: at n = 1600 it is
    within 1 % of the polynomial difference (measured 0.6 %)."""
    scene = SCENE.replace(creep=0.5 * XI_SAT)
    coulomb = scene.replace(friction=Coulomb(0.3))
    poly = split_solve(scene).tangential_force_per_length - solve(coulomb).tangential_force_per_length
    disc = (solve(scene, method="discretised", elements=1600).tangential_force_per_length
            - solve(coulomb, method="discretised", elements=1600).tangential_force_per_length)
    assert poly < 0.0 and disc == pytest.approx(poly, rel=1e-2), (poly, disc)


@pytest.mark.parametrize("law", [LAW, STEEP], ids=["B = 3 s/m", "B = 30 s/m"])
@pytest.mark.parametrize("ratio", [0.1, 0.9])
def test_error_estimate_bounds_the_error_against_four_times_the_nodes(law, ratio):
    scene = SCENE.replace(creep=ratio * XI_SAT, friction=law)
    r = split_solve(scene)
    fine = split_solve(scene, nodes=4 * r.info["nodes"])
    error = abs(r.tangential_force_per_length / fine.tangential_force_per_length - 1.0)
    assert r.success and fine.success
    assert error <= r.residual, f"error {error:.3g} above the estimate {r.residual:.3g}"
    assert r.residual <= 1e-3, "the default nodes give 1e-3 on these laws"


def test_sign_zero_creep_and_full_slip():
    r = split_solve(SCENE.replace(creep=0.5 * XI_SAT))
    mirrored = split_solve(SCENE.replace(creep=-0.5 * XI_SAT))
    assert mirrored.tangential_force_per_length == -r.tangential_force_per_length
    zero = solve(SCENE.replace(creep=0.0), method="polynomial")
    assert zero.success and zero.tangential_force_per_length == 0.0, zero.message
    full = split_solve(SCENE.replace(creep=3.0 * XI_SAT))
    assert full.success and full.stick_half_width == 0.0, full.message
    # in full slip mu falls below mu_s everywhere
    assert 0.12 * LOAD < full.tangential_force_per_length < 0.3 * LOAD


@pytest.mark.parametrize("ratio", [0.0, 0.1, 0.5, 0.9, 2.0])
def test_creep_stiffness_is_the_slope_of_the_creep_curve(ratio):
    """dT'/dxi (a one-sided difference over a warm-started perturbed solution) against the central difference of
    two independent solves 1e-5 of saturation either side (both from the Coulomb start): within 2e-4 (the discrete
    solution's kinks where the stick/slip boundary crosses a node; 6e-5 measured); in full slip negative, mu falling
    with the slip."""
    creep = ratio * XI_SAT
    r = split_solve(SCENE.replace(creep=creep))
    assert r.success and math.isfinite(r.creep_stiffness_per_length), r.message
    h = 1e-5 * XI_SAT
    up, down = (split_solve(SCENE.replace(creep=creep + d)).tangential_force_per_length for d in (h, -h))
    assert r.creep_stiffness_per_length == pytest.approx((up - down) / (2 * h), rel=2e-4, abs=1e-6 * LOAD / XI_SAT)
    if ratio > 1.0:
        assert r.creep_stiffness_per_length < 0.0


def test_force_is_continuous_in_the_law_and_falls_with_it():
    """T' from B = 0 (Coulomb) up: continuous (steps of B change it by steps of their size) and decreasing."""
    forces = [split_solve(SCENE.replace(creep=0.5 * XI_SAT), friction=ExponentialFalling(0.3, 0.4, b))
              .tangential_force_per_length for b in (1e-9, 0.5, 1.0, 1.5)]
    steps = np.diff(forces)
    assert (steps < 0.0).all(), forces
    assert abs(steps[2] - steps[1]) <= 0.2 * abs(steps[1]), f"steps of B = 0.5 s/m change T' unevenly: {steps}"


@pytest.mark.parametrize("tolerance", [1e-2, 1e-4])
def test_auto_solves_a_split_contact_with_a_falling_law_by_the_polynomial_method(tolerance):
    auto = solve(SCENE.replace(creep=0.5 * XI_SAT), tolerance=tolerance)
    assert auto.success and auto.method == "polynomial" and len(auto.info["patches"]) == 2, auto.message
    assert auto.info["tolerance_met"] and auto.info["error_estimate"] <= tolerance


def test_satellite_scene_agrees_with_the_discretised_active_set():
    """The 6 mm scene of tests/test_multipatch.py, a small satellite ahead of the main patch: the satellite slips
    throughout and the main patch sticks at its leading edge; the discretised slip iteration (whose certificate
    checks the traction bound and the slip direction on every element) finds the same stick zone to two elements
    and a T' within its error estimate."""
    scene = corrugated(0.006, 0.0045)
    r = solve(scene, method="polynomial")
    assert r.success and len(r.info["patches"]) == 2, r.message
    (satellite, _) = r.info["stick_zones"]
    assert satellite[0] == satellite[1], "the satellite slips throughout"
    assert_agrees_with_the_discretised(r, scene, 800)


def test_small_creep_on_mirror_patches_starts_from_the_coulomb_stick_zones():
    """10 mm / 10 um with the axis over a crest of the gap (two mirror patches) at 0.1 of saturation: from full slip
    (q1 = mu_s p, no stick zones) the first sweep's field of the trailing patch reverses the leading patch's creep
    and its slip iteration has no solution; from Coulomb's stick zones and corrections with mu_s the sweeps
    converge, to the discretised slip iteration's T' within its estimate and its stick zones within two elements."""
    from rollcontact.line.methods.polynomial.patches_slip import coupled_iteration

    scene = corrugated(0.010, 0.005, creep=0.1 * XI_SAT).replace(
        surface=Surface(harmonics=(Harmonic.from_wavelength(0.010, 10e-6),)))
    expansion = SlopeExpansion(scene.radius, scene.axis_position, scene.surface)
    normal = patches.split_normal(expansion, LOAD, ESTAR, patches.patch_starts(scene, None)[0], 1e-12, None)
    *_, failure = coupled_iteration(normal, ESTAR, LAW, SPEED, scene.creep, 32, XI_SAT)
    assert "did not converge" in failure, "the premise: the iteration from full slip fails"
    r = solve(scene, method="polynomial")
    assert r.success and len(r.info["patches"]) == 2, r.message
    assert_agrees_with_the_discretised(r, scene, 1600)


def test_a_traction_above_the_bound_is_reported():
    """The validity check on the fields: a stick-zone correction of the wrong sign puts |q| above mu_s p."""
    from dataclasses import replace

    from rollcontact.line.methods.polynomial.patches_slip import tangential_failures

    r = split_solve(SCENE.replace(creep=0.5 * XI_SAT))
    assert tangential_failures(r.distributions, 0.3, XI_SAT) == []
    wrong = replace(r.distributions, stick_coefficients=tuple(-f for f in r.distributions.stick_coefficients))
    assert any("traction bound" in text for text in tangential_failures(wrong, 0.3, XI_SAT))


def test_no_slip_iteration_on_a_single_patch_that_is_not_the_contact(monkeypatch):
    """A corrugation so short that the contact has more patches than the method takes: the single patch's normal
    solution fails its checks and so do the patches; the result says why at once, without the single patch's slip
    iteration (which at the hundreds of nodes such a pressure needs took seconds, for a result that fails anyway)."""
    from rollcontact.line.methods.polynomial import solver

    def refuse(*args, **kwargs):
        raise AssertionError("the slip iteration ran on a patch known not to be the contact")

    monkeypatch.setattr(solver, "solve_velocity_dependent", refuse)
    r = solve(corrugated(0.0004, 0.0), method="polynomial")
    assert not r.success and "contact splits" in r.message and "patches found" in r.message, r.message
