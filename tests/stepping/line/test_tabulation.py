"""The interpolation and onset search the certified tables share (rollcontact.stepping.line.tabulation)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollcontact.stepping.line import tabulation as tb


def test_the_chebyshev_interpolant_reproduces_a_polynomial_of_its_degree():
    nodes, weights = tb.chebyshev_points(7), tb.barycentric_weights(7)
    values = np.polynomial.polynomial.polyval(nodes, [0.3, -1.0, 2.0, 0.5, -0.7, 1.1, 0.2])
    for x in (0.0, 1e-15, 0.123, nodes[3], 0.77, 1.0 - 1e-15, 1.0):
        exact = np.polynomial.polynomial.polyval(x, [0.3, -1.0, 2.0, 0.5, -0.7, 1.1, 0.2])
        assert tb.basis(x, nodes, weights) @ values == pytest.approx(exact, abs=1e-13), f"x = {x}"


def test_the_periodic_interpolant_reproduces_a_trigonometric_polynomial_of_its_degree():
    nodes = tb.periodic_points(9)  # degree 4
    f = lambda t: 0.2 + np.cos(t) - 0.3 * np.sin(2 * t) + 0.05 * np.cos(4 * t + 0.3)  # noqa: E731
    for theta in (0.0, 1e-15, 0.5, nodes[4], 3.0, 2.0 * math.pi - 1e-15):
        assert tb.periodic_basis(theta, nodes) @ f(nodes) == pytest.approx(f(theta), abs=1e-13), f"theta = {theta}"


def test_the_tails_see_what_the_grid_does_not_resolve():
    cheb = tb.chebyshev_points(9)
    smooth = np.vstack([cheb ** 3, 1.0 - cheb])
    assert tb.chebyshev_tail(smooth, 1) < 1e-14, "a cubic has no coefficients beyond degree 3"
    assert tb.chebyshev_tail(np.exp(-40.0 * cheb)[None], 1) > 1e-3, "a steep exponential is not resolved by 9 points"
    theta = tb.periodic_points(11)
    assert tb.periodic_tail(np.cos(theta)[None], 1) < 1e-14, "one harmonic of 5 resolved"
    assert tb.periodic_tail(np.cos(5 * theta)[None], 1) == pytest.approx(1.0), "the highest harmonic, amplitude 1"


@pytest.mark.parametrize("curvature", [0.0, 0.3, -0.3])
def test_the_onset_search_finds_where_the_stick_zone_vanishes_in_few_solves(curvature):
    root = 1.0797289482443126
    calls = []

    def node(u):
        calls.append(u)
        yield
        s = 1.0 - u / root
        return tb.Node(0.0, max(0.0, s * (1.0 + curvature * s)), 0.0, 0.0)

    search = tb.onset(node)
    try:
        while True:
            next(search)
    except StopIteration as stop:
        found = stop.value
    assert abs(found - root) <= 1e-10 * root, f"onset {found!r} against {root!r}"
    assert found >= root, "the onset returned is in full slip (a*/a = 0)"
    assert len(calls) <= 25, f"{len(calls)} solves"
