"""What the certified tables of :mod:`rollcontact.stepping.line.table` share: their target, interpolation on
Chebyshev and periodic points, the estimate of an interpolant's truncation error and the search for the onset of full
slip.

Interpolation
-------------
On ``[0, 1]`` the nodes are Chebyshev points of the second kind (both ends included) and the interpolant is the
barycentric formula with the weights ``(-1)^j`` halved at the ends (Berrut & Trefethen, "Barycentric Lagrange
interpolation", SIAM Review 46 (2004), eq 5.2), ``p(x) = sum_j w_j f_j / (x - x_j) / sum_j w_j / (x - x_j)``.  Over
a period ``[0, 2 pi)`` the nodes are ``M`` equispaced points (``M`` odd) and the trigonometric interpolant of degree
``(M - 1)/2`` is ``p(theta) = sum_j (-1)^j f_j / sin((theta - theta_j)/2) / sum_j (-1)^j / sin((theta - theta_j)/2)``
(the same reference, eq 6.1 for odd M).  Both converge geometrically for analytic functions; the size of the last
coefficients of the expansion (Chebyshev coefficients by a type-I DCT, Fourier coefficients by an FFT) estimates
what a finer grid would change, which tells a table the direction to refine.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft

TARGET = 1e-3
"""Error of tau = T'/(mu N') [1] a table must stay within (the FMU's real-time aim, docs/accuracy.md)."""

NODE_TOLERANCE = 1e-4
"""Requested accuracy of the exact solves at the nodes (relative error of T')."""

MAX_NODES = 65
"""Largest node count per direction: beyond it the table is given up (the steps solve exactly)."""

TWO_PI = 2.0 * np.pi


def chebyshev_points(n: int) -> np.ndarray:
    """Chebyshev points of the second kind on [0, 1], both ends included, ascending."""
    return 0.5 - 0.5 * np.cos(np.pi * np.arange(n) / (n - 1))


def barycentric_weights(n: int) -> np.ndarray:
    """Barycentric weights of the Chebyshev points of the second kind: (-1)^j, halved at the ends."""
    weights = (-1.0) ** np.arange(n)
    weights[[0, -1]] *= 0.5
    return weights


def basis(x: float, nodes: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Normalised barycentric coefficients at x in [0, 1]: the interpolant is ``coefficients @ values``.

    x within 1e-13 of an end is taken at that end (its difference to the end node could underflow); x on a node
    gives that node's value, with no division by zero (interior nodes are more than 1e-13 from any other double
    that rounds onto them).
    """
    if x < 1e-13:
        x = 0.0
    elif x > 1.0 - 1e-13:
        x = 1.0
    difference = x - nodes
    if difference.all():
        c = weights / difference
        return c / c.sum()
    out = np.zeros(nodes.size)
    out[int(np.abs(difference).argmin())] = 1.0
    return out


def coefficient_rows(points: list[float], nodes: np.ndarray, weights: np.ndarray, node_set: set) -> np.ndarray:
    """The coefficients a table's step contracts with at each of ``points`` in [0, 1], one row each (m, nodes):
    ``weights / (x - nodes)`` (unnormalised) for a point inside and on no node, :func:`basis` otherwise (``node_set``:
    the table's nodes of every direction, as its ``evaluate`` tests them).  The rows of the first kind are one
    vectorised subtraction and division, the same correctly rounded operations per element as ``evaluate``'s, so each
    row is bit for bit the vector ``evaluate`` builds for its point."""
    if min(points) > 1e-13 and max(points) < 1.0 - 1e-13 and node_set.isdisjoint(points):
        return np.divide(weights, np.subtract.outer(points, nodes))
    return np.array([weights / (x - nodes) if 1e-13 < x < 1.0 - 1e-13 and x not in node_set else
                     basis(x, nodes, weights) for x in points])


def contract(stacked: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``stacked[i] @ rows[i]`` for every i, (m, R): ``stacked`` (m, R, K), ``rows`` (m, K).

    numpy's stacked matmul ``(m, R, K) @ (m, K, 1)`` calls BLAS gemv once per item, as ``matrix @ vector`` does in a
    table's ``evaluate``, so every product is bit for bit the single one (``tests/stepping/test_contacts.py`` checks it
    over random matrices; a plain ``(R, K) @ (K, m)`` would call gemm, which rounds otherwise)."""
    return (stacked @ rows[:, :, None]).reshape(rows.shape[0], -1)


def periodic_points(m: int) -> np.ndarray:
    """m equispaced points ``2 pi j / m`` of the period [0, 2 pi)."""
    return TWO_PI * np.arange(m) / m


def periodic_basis(theta: float, nodes: np.ndarray) -> np.ndarray:
    """Normalised coefficients of the trigonometric interpolant at theta in [0, 2 pi) on an odd number of
    :func:`periodic_points`: the interpolant is ``coefficients @ values``."""
    if theta < 1e-13 or theta > TWO_PI - 1e-13:
        theta = 0.0
    s = np.sin(0.5 * (theta - nodes))
    if s.all():
        c = np.where(np.arange(nodes.size) % 2 == 0, 1.0, -1.0) / s
        return c / c.sum()
    out = np.zeros(nodes.size)
    out[int(np.abs(s).argmin())] = 1.0
    return out


def chebyshev_tail(values: np.ndarray, axis: int) -> float:
    """Largest |coefficient| among the last two of the Chebyshev expansions of ``values`` along ``axis`` (on
    :func:`chebyshev_points`): the change a finer grid would bring, in the values' units."""
    n = values.shape[axis]
    coefficients = scipy.fft.dct(values, type=1, axis=axis) / (n - 1)
    return float(np.abs(np.take(coefficients, [n - 2, n - 1], axis=axis)).max())


def periodic_tail(values: np.ndarray, axis: int) -> float:
    """Largest |coefficient| of the highest two frequencies of the trigonometric interpolants of ``values`` along
    ``axis`` (on an odd number of :func:`periodic_points`)."""
    m = values.shape[axis]
    spectrum = np.abs(np.fft.rfft(values, axis=axis)) * (2.0 / m)
    top = spectrum.shape[axis]
    return float(np.take(spectrum, [top - 2, top - 1], axis=axis).max())


class CertifiedTable:
    """What both tables share: the driver of a build and its bound on the work.

    A table defines ``exact(*coordinates)`` (one exact solve, counted in ``solves``), ``build_steps()`` (a
    generator yielding once per solve, ready at its end) and ``max_solves``.
    """

    max_solves = 0
    """Exact solves after which a build is given up: bounds the work of any build (a state's domain included)."""

    def build(self):
        """``build_steps`` to the end: ready afterwards."""
        for _ in self.build_steps():
            pass
        return self

    def node(self, *coordinates):
        """``exact(*coordinates)`` as a step of a build: yields once after the solve, returns its value; the
        ``max_solves``-th solve gives the build up (ArithmeticError)."""
        if self.solves >= self.max_solves:
            raise ArithmeticError(f"the table does not meet {TARGET:g} mu N within {self.max_solves} exact solves")
        value = self.exact(*coordinates)
        yield
        return value


@dataclass(frozen=True)
class Node:
    """The normalised solution at one point of a table: tau, a*/a, kappa and the solve's error estimate (relative
    error of T')."""

    tau: float
    alpha: float
    kappa: float
    estimate: float


def onset(node, start: float = 0.5):
    """The creep (in the table's unit) of the onset of full slip, where the stick zone vanishes (a build-step
    generator: ``node(u)`` is one, returning the :class:`Node` at creep u).

    a*/a is smooth and nearly linear in partial slip (Carter's ``1 - u``) and zero in full slip.  From below, a
    Newton step (its slope by a one-sided difference) is taken while it stays under the lowest full-slip creep met
    (``high``).  A concave a*/a makes it overshoot the onset by the square of its distance, so the step after an
    overshoot goes back from ``high`` by a fraction of the bracket, 0.1 % first and ten times more at every
    further full-slip result (at most half: bisection).  The search ends when the bracket is within a relative 1e-10.
    """
    low, high = 0.0, None
    u = start
    fraction = 1e-3
    for _ in range(60):
        value = yield from node(u)
        if value.alpha > 0.0:
            low = u
            fraction = 1e-3
            below = yield from node(u * (1.0 - 1e-4))
            slope = (value.alpha - below.alpha) / (1e-4 * u)
            u = u + (value.alpha / -slope if slope < 0.0 else u)
            if high is not None and u >= high:
                u = high - fraction * (high - low)
        else:
            high = u
            u = high - fraction * (high - low)
            fraction = min(0.5, 10.0 * fraction)
        if high is not None and high - low <= 1e-10 * high:
            return high
    return high if high is not None else u
