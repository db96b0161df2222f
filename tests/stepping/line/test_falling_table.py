"""The certified table of falling friction on a flat surface (rollcontact.stepping.line.falling_table): the scaling it
rests on, its bound at random points and the end of its domain.  Its use by the stepping model: test_table.py."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rollcontact as rc
from rollcontact.stepping.line.falling_table import FallingFrictionTable
from rollcontact.stepping.line.tabulation import TARGET

MU, A, R = 0.3, 0.6, 0.46
E_STAR = rc.Material().contact_modulus


@pytest.fixture(scope="module")
def table() -> FallingFrictionTable:
    return FallingFrictionTable(A, 1.5).build()


def normalised(load: float, u: float, w: float, decay: float) -> tuple[float, float, float]:
    a = rc.hertz(load, R, E_STAR)[0]
    saturation = MU * a / R
    scene = rc.Scene(load, creep=u * saturation, radius=R, friction=rc.ExponentialFalling(MU, A, decay),
                     rolling_speed=w / (decay * saturation))
    result = rc.solve(scene, method="polynomial", tolerance=1e-4)
    return (result.tangential_force_per_length / (MU * load), result.stick_half_width / a,
            result.creep_stiffness_per_length * saturation / (MU * load))


@pytest.mark.parametrize(("u", "w"), [(0.3, 0.4), (0.8, 1.2), (3.0, 0.7)])
def test_the_normalised_solution_depends_on_u_and_w_alone(u, w):
    one, other = normalised(1e6, u, w, 1.0), normalised(4e6, u, w, 7.0)
    assert one == pytest.approx(other, rel=1e-9, abs=1e-12), f"u = {u}, w = {w}: {one} against {other}"


@settings(max_examples=25, deadline=None, derandomize=True)
@given(u=st.floats(0.0, 12.0), w=st.floats(0.0, 1.5))
def test_the_certified_bound_holds_at_random_points(table, u, w):
    tau = table.evaluate(u, w)[0]
    exact = table.exact(u, w).tau
    assert abs(tau - exact) <= table.bound, f"u = {u}, w = {w}: |{tau} - {exact}| above the bound {table.bound:.3g}"


def test_the_bound_meets_the_target_and_the_domain_ends_at_w_max(table):
    assert table.ready and table.bound <= TARGET, f"bound {table.bound}"
    assert table.evaluate(0.5, 1.6) is None, "beyond w_max: no answer"
