"""The certified table of the elliptic strips (rollcontact.stepping.elliptic.table): the similarity it rests on, a
build repeated bit for bit, answers within the bound at random points it was not built on, its derivatives, its
symmetries and the planned work of a build."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact import EllipticScene, Material
from rollcontact.core.friction import Coulomb
from rollcontact.elliptic.creep_coefficients import creepage_coefficients
from rollcontact.elliptic.methods.strips import solve_strips
from rollcontact.stepping.elliptic.table import EllipticTable, cached_table

SMALL = (5, 9, 7, 5)
"""Node counts of the table of these tests (some 5000 strips solves): coarse, its bound some 0.3 mu Fn."""


@pytest.fixture(scope="module")
def table() -> EllipticTable:
    return EllipticTable(0.28, SMALL).build()


def normalised(scene: EllipticScene) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    """The strips' ``(tau_x, tau_y, tau_z)`` of the scene and its ``(rho, u_x, u_y, u_s)`` (the table's module
    docstring)."""
    h = scene.hertz
    c = creepage_coefficients(h.aspect_ratio, scene.material.poisson_ratio)
    limit = scene.friction_coefficient * scene.normal_load
    k = scene.shear_modulus * h.c * h.c / limit
    u = (k * c.c11 * scene.longitudinal_creepage, k * c.c22 * scene.lateral_creepage,
         k * (c.c23 * h.c + 0.5 * c.c11 * h.b) * scene.spin_creepage)
    r = solve_strips(scene)
    return (r.longitudinal_force / limit, r.lateral_force / limit, r.spin_moment / (limit * h.c)), (
        math.log(h.aspect_ratio), *u)


def random_scene(rng, spin: bool = True, nu: float = 0.28) -> EllipticScene:
    """A scene of random load, size, material, friction coefficient and a/b 0.1..10, creepages of either sign up
    to a few saturation values."""
    load, mu, modulus = rng.uniform(1e3, 3e5), rng.uniform(0.05, 0.8), rng.uniform(5e10, 3e11)
    A = rng.uniform(0.2, 5.0)
    B = A * math.exp(rng.uniform(-3.0, 3.0))
    scene = EllipticScene(load, A, B, material=Material(modulus, nu), friction=Coulomb(mu))
    while not 0.1 <= scene.hertz.aspect_ratio <= 10.0:
        B = A * math.exp(rng.uniform(-2.0, 2.0))
        scene = EllipticScene(load, A, B, material=Material(modulus, nu), friction=Coulomb(mu))
    saturation = mu * load / (scene.shear_modulus * scene.hertz.c**2 * 4.0)
    spin_creepage = rng.normal(0.0, 3.0 * saturation / scene.hertz.c) if spin else 0.0
    return scene.replace(longitudinal_creepage=rng.normal(0.0, 2.0 * saturation),
                         lateral_creepage=rng.normal(0.0, 2.0 * saturation), spin_creepage=spin_creepage)


def test_the_strips_normalised_forces_depend_on_a_b_nu_and_the_normalised_creepages_alone():
    """Scenes of the same a/b, nu and normalised creepages, at other loads, sizes, moduli and friction coefficients:
    the same normalised forces to rounding (the similarity the table rests on)."""
    rng = np.random.default_rng(2)
    for _ in range(12):
        first = random_scene(rng, spin=bool(rng.integers(2)))
        forces, (rho, ux, uy, us) = normalised(first)
        scale = rng.uniform(0.3, 3.0)
        other = EllipticScene.from_semi_axes(rng.uniform(1e3, 3e5), first.hertz.a * scale, first.hertz.b * scale,
                                             Material(rng.uniform(5e10, 3e11), 0.28), friction=Coulomb(0.45))
        h = other.hertz
        c = creepage_coefficients(h.aspect_ratio, 0.28)
        k = other.friction_coefficient * other.normal_load / (other.shear_modulus * h.c * h.c)
        other = other.replace(longitudinal_creepage=ux * k / c.c11, lateral_creepage=uy * k / c.c22,
                              spin_creepage=us * k / (c.c23 * h.c + 0.5 * c.c11 * h.b))
        again, _ = normalised(other)
        assert np.allclose(again, forces, rtol=0.0, atol=1e-9), f"{again} != {forces} at u = {(ux, uy, us)}"


def test_a_build_repeats_bit_for_bit_and_takes_its_planned_batches():
    first, second = EllipticTable(0.3, (3, 5, 3, 3)), EllipticTable(0.3, (3, 5, 3, 3))
    batches = list(first.build_steps())
    second.build()
    assert batches == first.batch_sizes(), "one yield per planned batch, of its planned size"
    assert first.solves == second.solves == sum(batches) == first.solves_planned(), "the planned solves"
    for name in first.tables:
        assert np.array_equal(first.tables[name].data, second.tables[name].data), f"table {name}: bit for bit"
    assert first.bound == second.bound and first.check_error == second.check_error, "the certificate too"
    assert cached_table(0.3, (3, 5, 3, 3)) is None, "a table is kept for the process only when a model builds it"


def test_the_answers_are_within_the_bound_at_random_points_not_built_on(table):
    """Random scenes (random a/b, load, size, material, friction coefficient, creepages of either sign, with spin and
    without): the table's forces against the strips', within its certified bound."""
    rng = np.random.default_rng(5)
    worst = 0.0
    for n in range(150):
        forces, query = normalised(random_scene(rng, spin=n % 4 != 0))
        answer = table.answer(*query, False)
        worst = max(worst, *(abs(a - b) for a, b in zip(answer[:3], forces, strict=True)))
    assert 0.0 < worst <= table.bound, f"largest error {worst:.3g} against the bound {table.bound:.3g}"


def test_the_symmetries_hold_in_the_answers(table):
    """Reversing every creepage reverses every force; the mirror (eta, phi) -> (-eta, -phi) keeps Fx and reverses Fy
    and Mz; the derivatives follow."""
    rng = np.random.default_rng(8)
    for _ in range(20):
        rho, ux, uy, us = rng.uniform(-2.3, 2.3), *rng.normal(0.0, 1.5, 2), rng.choice([0.0, rng.normal(0.0, 3.0)])
        tx, ty, tz, d = table.answer(rho, ux, uy, us, True)
        rx, ry, rz, dr = table.answer(rho, -ux, -uy, -us, True)
        assert (rx, ry, rz) == (-tx, -ty, -tz), "reversal"
        mx, my, mz, dm = table.answer(rho, ux, -uy, -us, True)
        assert (mx, my, mz) == (tx, -ty, -tz), "mirror"
        assert dr == d or us == 0.0, "the derivatives of the reversed creepages are the same"
        flips = (1, -1, -1, -1, 1, 1, -1, 1, 1)
        assert us == 0.0 or all(a == f * b for a, f, b in zip(dm, flips, d, strict=True)), "mirrored derivatives"


@pytest.mark.parametrize("query", [(0.3, 0.5, 0.8, -0.4), (-1.2, 1.4, 0.2, 2.5), (1.9, 0.3, -0.6, 0.9),
                                   (0.0, -0.7, 0.4, 0.0)])
def test_the_derivatives_are_those_of_the_answers(table, query):
    """Central differences of the table's own answers against its derivatives (inside cells, away from spin 0 where
    the strips jump, and for no spin in u_x and u_y)."""
    *_, derivatives = table.answer(*query, True)
    columns = 2 if query[3] == 0.0 else 3
    for j in range(columns):
        step = 1e-6
        up, down = list(query), list(query)
        up[1 + j] += step
        down[1 + j] -= step
        difference = (np.array(table.answer(*up, False)[:3]) - np.array(table.answer(*down, False)[:3])) / (2 * step)
        assert np.allclose(difference, derivatives[j::3], rtol=0.0, atol=1e-6), \
            f"column {j}: {difference} != {derivatives[j::3]}"


def test_the_answers_do_not_depend_on_the_other_calls(table):
    rng = np.random.default_rng(1)
    queries = [(rng.uniform(-2.3, 2.3), *rng.normal(0.0, 1.0, 2), rng.choice([0.0, rng.normal(0.0, 2.0)]))
               for _ in range(20)]
    first = [table.answer(*q, True) for q in queries]
    assert [table.answer(*q, True) for q in reversed(queries)] == first[::-1], "a function of its arguments"
