"""The certified table of Coulomb friction on a corrugated surface of one harmonic (used by
:mod:`rollcontact.stepping.line.table`).

On a surface ``Z(X) = Phi cos(k X) + Psi sin(k X)`` (plus a constant) with Coulomb friction mu, the steady solution
for the axis at X, the load per length N' and the creep xi is periodic in X with the wavelength ``2 pi / k`` and does
not depend on the rolling speed.  At each phase ``theta = k X mod 2 pi`` and load, the normal problem fixes the patch
(half-width a, offset, peak pressure p0); the tangential problem with Coulomb friction is odd in the creep (``q -> -q``
and ``xi -> -xi`` keep the stick and slip zones), in partial slip up to the onset of full slip ``xi_fs(theta, N')``
and in full slip beyond it, where ``T' = mu N'`` exactly, ``a* = 0`` and ``dT'/dxi = 0``.  In the units of the flat
surface at the same load (Hertz's ``a_H`` and ``p0_H``, Carter's saturation creep ``xi_H = mu a_H / R``) every
quantity is of order one, and :class:`CorrugationTable` interpolates them on a tensor grid

* in the phase theta: an odd number M of equispaced points, trigonometric interpolation (the solution is periodic
  and analytic in theta while the contact is one patch);
* in the load: ``l = ln(N'/N_low) / ln(N_high/N_low)`` in [0, 1] on Chebyshev points;
* in partial slip: ``t = |xi| / xi_fs`` in [0, 1] on Chebyshev points (the onset is an end of the grid, so the kink
  of the creep curve there is not inside it).

At each (theta, l) node it holds ``a/a_H``, ``offset/a_H``, ``p0/p0_H`` and ``v_fs = xi_fs/xi_H`` (found by
:func:`rollcontact.stepping.line.tabulation.onset`), and at each t node ``tau = T'/(mu N')``, ``a*/a`` and
``kappa = dtau/dt = (dT'/dxi) xi_fs / (mu N')``.  The nodes are solved by the polynomial method at
:data:`~rollcontact.stepping.line.tabulation.NODE_TOLERANCE`.

The table is certified a posteriori: at the joint midpoints (theta between nodes, l between nodes and at both ends, t
between nodes and at the onset) the exact solution is compared with the interpolant, for tau and for the normal
quantities (a/a_H, offset/a_H, p0/p0_H).  While the largest difference exceeds half the target, the directions whose
interpolants' last coefficients (:func:`~rollcontact.stepping.line.tabulation.periodic_tail`,
:func:`~rollcontact.stepping.line.tabulation.chebyshev_tail`) are not small are refined; the bound the table reports is
``2 max|difference| + the nodes' largest error estimate`` [1 of mu N'], and a/a_H, offset/a_H and p0/p0_H are held
within it too.  A contact that splits into several patches anywhere on the grid or at a check point gives the table
up (the steps solve exactly), as does a load outside ``[N_low, N_high]`` for one step.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from rollcontact.line.dispatch import solve
from rollcontact.line.scene import Scene
from rollcontact.stepping.line.tabulation import (
    MAX_NODES,
    NODE_TOLERANCE,
    TARGET,
    TWO_PI,
    CertifiedTable,
    Node,
    barycentric_weights,
    basis,
    chebyshev_points,
    chebyshev_tail,
    coefficient_rows,
    contract,
    onset,
    periodic_basis,
    periodic_points,
    periodic_tail,
)

NODES = (13, 5, 9)
"""Starting node counts in theta (odd), in l and in t; each grows to ``2 n - 1`` while the check fails."""

EXPECTED_SOLVES = 2200
"""Exact solves a build is modelled to take (its nodes, their onsets and the check; ``benchmarks/bench_table.py``
reports the count)."""

SOLVE_COST = 1.2e-4
"""Modelled time [s] of one exact solve of a build: the mean of a build's solves (``benchmarks/bench_table.py``,
"Builds", seconds over solves), with which ``table`` = auto spreads a build over the exact steps."""

NORMAL = 5
"""Rows of the (theta, l) quantities ahead of the t nodes: v_fs, a/a_H, offset/a_H, p0/p0_H and ones (the ones
rows, here and after each t node's tau, a*/a and kappa, carry the barycentric normalisation through the
contractions of :meth:`CorrugationTable.evaluate`)."""


class CorrugationTable(CertifiedTable):
    """T', a, a*, offset, p0 and dT'/dxi of Coulomb friction on a one-harmonic surface, interpolated over (theta,
    l, t) (module docstring).

    Parameters
    ----------
    scene : callable
        ``scene(X, N', xi)``: the scene for the axis at X [m] (the stepping model's frame), N' [N/m] and xi [1].
    wavelength : float
        Of the harmonic [m]: the period in X.
    loads : (float, float)
        ``(N_low, N_high)`` [N/m], ``0 < N_low < N_high``: the loads per length the table covers.
    radius, contact_modulus, friction_coefficient
        R [m], E* [Pa] and mu [1] of the scene (the units of the table: Hertz and Carter on the flat surface).

    Attributes
    ----------
    bound : float
        Certified error of tau [1 of mu N'] (NaN until built).
    solves : int
        Exact solves it took.
    """

    max_solves = 10 * EXPECTED_SOLVES

    def __init__(self, scene: Callable[[float, float, float], Scene], wavelength: float, loads: tuple[float, float],
                 radius: float, contact_modulus: float, friction_coefficient: float):
        low, high = float(loads[0]), float(loads[1])
        if not 0.0 < low < high < math.inf:
            raise ValueError(f"loads = {loads!r} N/m must satisfy 0 < N_low < N_high < inf")
        self.scene, self.wavelength, self.loads = scene, float(wavelength), (low, high)
        self.wavenumber = TWO_PI / self.wavelength
        self.log_low, self.log_span = math.log(low), math.log(high / low)
        self.radius, self.contact_modulus, self.mu = float(radius), float(contact_modulus), float(friction_coefficient)
        self.width_factor = 4.0 * self.radius / (math.pi * self.contact_modulus)  # a_H^2 / N'
        self.bound = math.nan
        self.solves = 0
        self.ready = False

    @property
    def domain(self) -> tuple[float, float]:
        """``(N_low, N_high)`` [N/m]: what, with the parameters, determines the table."""
        return self.loads

    @property
    def nbytes(self) -> int:
        """Size of the interpolation data [bytes]."""
        return sum(a.nbytes for a in (self.data, self.theta_nodes, self.l_nodes, self.t_nodes))

    # ---------------------------------------------------------------------------------------------- exact nodes
    def units(self, load: float) -> tuple[float, float, float]:
        """Hertz's a_H [m], p0_H [Pa] and Carter's xi_H [1] of the flat surface at N' [N/m]."""
        a = math.sqrt(self.width_factor * load)
        return a, 2.0 * load / (math.pi * a), self.mu * a / self.radius

    def exact(self, theta: float, ell: float, v: float) -> tuple[Node, tuple[float, float, float]]:
        """The normalised solution at phase theta, load coordinate l and creep ``v = xi / xi_H`` by the polynomial
        method (one solve), and the normal quantities ``(a/a_H, offset/a_H, p0/p0_H)``.

        Raises
        ------
        ArithmeticError
            The solve fails or the contact is several patches.
        """
        load = math.exp(self.log_low + ell * self.log_span)
        a_h, p_h, xi_h = self.units(load)
        x = theta / self.wavenumber
        result = solve(self.scene(x, load, v * xi_h), method="polynomial", tolerance=NODE_TOLERANCE)
        self.solves += 1
        where = f"X = {x:.6g} m, N' = {load:.6g} N/m, creep = {v * xi_h:.6g}"
        if not result.success:
            raise ArithmeticError(f"table node {where}: {result.message}")
        if "patches" in result.info:
            raise ArithmeticError(f"the contact splits into {len(result.info['patches'])} patches at {where}")
        limit = self.mu * load
        a = result.contact_half_width
        node = Node(result.tangential_force_per_length / limit, result.stick_half_width / a,
                    result.creep_stiffness_per_length * xi_h / limit, float(result.info.get("error_estimate", 0.0)))
        return node, (a / a_h, result.contact_offset / a_h, result.max_pressure / p_h)

    def onset(self, theta: float, ell: float):
        """v_fs at (theta, l) (a build-step generator)."""
        return (yield from onset(lambda v: self.node_only(theta, ell, v), start=0.5))

    def node_only(self, theta: float, ell: float, v: float):
        """The :class:`Node` of :meth:`node` (a build-step generator)."""
        return (yield from self.node(theta, ell, v))[0]

    # ------------------------------------------------------------------------------------------------- build
    def build_steps(self):
        """Solve the nodes, check the joint midpoints, refine until the check meets
        :data:`~rollcontact.stepping.line.tabulation.TARGET`, one exact solve per iteration (a caller can spread the
        build over many steps); ready at the end.

        Raises
        ------
        ArithmeticError
            A node the exact solver cannot solve or that splits, or
            :data:`~rollcontact.stepping.line.tabulation.MAX_NODES` reached without meeting the target.
        """
        counts = list(NODES)
        while True:
            yield from self.tabulate(*counts)
            error = yield from self.check()
            if error <= 0.5 * TARGET:
                self.bound = 2.0 * error + self.node_error
                self.ready = True
                return
            refine = self.directions()
            if any(2 * counts[d] - 1 > MAX_NODES for d in refine):
                raise ArithmeticError(f"the corrugation table does not meet {TARGET:g} mu N with {MAX_NODES} nodes "
                                      f"per direction (check error {error:.3g}, nodes {counts})")
            for d in refine:
                counts[d] = 2 * counts[d] - 1

    def tabulate(self, m: int, n_l: int, n_t: int):
        """The nodes (a build-step generator): per (theta, l) node the onset, the normal quantities and the t nodes."""
        self.theta_nodes, self.l_nodes, self.t_nodes = periodic_points(m), chebyshev_points(n_l), chebyshev_points(n_t)
        self.half_nodes, self.theta_signs = 0.5 * self.theta_nodes, (-1.0) ** np.arange(m)
        self.node_set = {*self.theta_nodes.tolist(), *self.l_nodes.tolist(), *self.t_nodes.tolist()}
        self.l_weights, self.t_weights = barycentric_weights(n_l), barycentric_weights(n_t)
        data = np.ones((NORMAL + 4 * n_t, n_l, m))
        estimates = [0.0]
        for i, ell in enumerate(self.l_nodes):
            for j, theta in enumerate(self.theta_nodes):
                v_fs = yield from self.onset(theta, ell)
                data[0, i, j] = v_fs
                for k, t in enumerate(self.t_nodes):
                    node, normal = yield from self.node(theta, ell, t * v_fs)
                    data[[NORMAL + k, NORMAL + n_t + k, NORMAL + 2 * n_t + k], i, j] = node.tau, node.alpha, \
                        node.kappa * v_fs
                    estimates.append(node.estimate * abs(node.tau))
                data[1:NORMAL - 1, i, j] = normal
        self.data, self.flat = data, data.reshape(-1, m)
        self.node_error = max(estimates)

    def directions(self) -> list[int]:
        """The directions (0 theta, 1 l, 2 t) whose interpolants' last coefficients exceed a quarter of the target,
        or the one with the largest when none does."""
        n_t = self.t_nodes.size
        partial = self.data[NORMAL:].reshape(4, n_t, *self.data.shape[1:])
        tails = [periodic_tail(self.data, 2), chebyshev_tail(self.data, 1), chebyshev_tail(partial, 1)]
        refine = [d for d, tail in enumerate(tails) if tail > 0.25 * TARGET]
        return refine or [int(np.argmax(tails))]

    def check(self):
        """Largest difference of tau, a/a_H, offset/a_H and p0/p0_H [1] between the interpolant and the exact solution
        at the joint midpoints (a build-step generator)."""
        theta_check = self.theta_nodes + np.pi / self.theta_nodes.size
        mid = 0.5 * (self.l_nodes[1:] + self.l_nodes[:-1])
        l_check = np.concatenate(([0.0], mid, [1.0]))
        t_check = np.concatenate((0.5 * (self.t_nodes[1:] + self.t_nodes[:-1]), [1.0]))
        error = 0.0
        for ell in l_check:
            load = math.exp(self.log_low + ell * self.log_span)
            a_h, p_h, xi_h = self.units(load)
            for theta in theta_check:
                x = theta / self.wavenumber
                v_fs = float(self.interpolate(theta, ell)[0])
                for t in t_check:
                    node, normal = yield from self.node(theta, ell, t * v_fs)
                    force, a, _, offset, p0, _ = self.evaluate(x, load, t * v_fs * xi_h)
                    error = max(error, abs(force / (self.mu * load) - node.tau), abs(a / a_h - normal[0]),
                                abs(offset / a_h - normal[1]), abs(p0 / p_h - normal[2]))
        return error

    # ---------------------------------------------------------------------------------------------- evaluate
    def interpolate(self, theta: float, ell: float) -> np.ndarray:
        """All rows of the table at (theta, l): the (theta, l) quantities, then tau, a*/a and kappa per t node."""
        return (self.data @ periodic_basis(theta, self.theta_nodes)) @ basis(ell, self.l_nodes, self.l_weights)

    def evaluate(self, x: float, load: float, creep: float) -> tuple[float, ...] | None:
        """``(T' [N/m], a [m], a* [m], offset [m], p0 [Pa], dT'/dxi [N/m])`` for the axis at X [m], N' [N/m] and the
        creep, or None for a load outside the table's; the offset is the scene's (``Result.contact_offset``).

        The same interpolants as :meth:`interpolate` and :func:`~rollcontact.stepping.line.tabulation.basis`, written
        for the step: the barycentric sums are normalised once, on the scalars, and a coordinate at the ends or equal to
        a node (of any direction: a set lookup) takes the general path.
        """
        ell = (math.log(load) - self.log_low) / self.log_span
        if not -1e-12 <= ell <= 1.0 + 1e-12:  # the ends' loads round-trip through exp and log within 1e-12
            return None
        theta = (x * self.wavenumber) % TWO_PI
        if (1e-13 < ell < 1.0 - 1e-13 and 1e-13 < theta < TWO_PI - 1e-13 and ell not in self.node_set
                and theta not in self.node_set):
            in_theta = self.flat @ (self.theta_signs / np.sin(0.5 * theta - self.half_nodes))
            rows = in_theta.reshape(-1, self.l_nodes.size) @ (self.l_weights / (ell - self.l_nodes))
        else:
            rows = self.interpolate(theta, ell)
        normal = self.normal(rows[:NORMAL].tolist(), load, creep)
        t = normal[5]
        if t >= 1.0:
            return self.answer(normal, creep)
        if 1e-13 < t < 1.0 - 1e-13 and t not in self.node_set:
            partial = (rows[NORMAL:].reshape(4, -1) @ (self.t_weights / (t - self.t_nodes))).tolist()
        else:
            partial = (rows[NORMAL:].reshape(4, -1) @ basis(t, self.t_nodes, self.t_weights)).tolist()
        return self.answer(normal, creep, partial)

    def normal(self, values: list[float], load: float, creep: float) -> tuple[float, ...]:
        """From the (theta, l) rows at a point (``v_fs, a/a_H, offset/a_H, p0/p0_H`` unnormalised and their barycentric
        sum) at N' [N/m] and the creep: ``(a [m], offset [m], p0 [Pa], mu N' [N/m], xi_fs [1], t = |xi| / xi_fs)``."""
        v_fs, a, offset, p0, scale = values
        a_h = math.sqrt(self.width_factor * load)
        xi_fs = v_fs / scale * self.mu * a_h / self.radius
        return (a * (a_h / scale), offset * (a_h / scale), p0 * (2.0 * load / (math.pi * a_h * scale)), self.mu * load,
                xi_fs, abs(creep) / xi_fs)

    @staticmethod
    def answer(normal: tuple[float, ...], creep: float, partial: list[float] | None = None) -> tuple[float, ...]:
        """:meth:`evaluate`'s answer from :meth:`normal` and, in partial slip, the t rows' ``(tau, a*/a, kappa)``
        unnormalised and their barycentric sum; full slip without them: ``T' = mu N'``, ``a* = 0``, ``dT'/dxi = 0``."""
        a, offset, p0, limit, xi_fs, _ = normal
        if partial is None:
            return math.copysign(limit, creep), a, 0.0, offset, p0, 0.0
        tau, alpha, kappa, scale = partial
        return (math.copysign(tau * limit / scale, creep) if creep != 0.0 else 0.0, a, alpha / scale * a, offset, p0,
                kappa * limit / (scale * xi_fs))

def evaluate_together(tables: list[CorrugationTable], stacked: np.ndarray, xs: list[float], loads: list[float],
                      creeps: list[float]) -> list[tuple[float, ...] | None]:
    """:meth:`CorrugationTable.evaluate` of each of ``tables`` at its ``(X, N', creep)``, bit for bit, with each
    contraction of all of them in one stacked matrix product (:func:`~rollcontact.stepping.line.tabulation.contract`).

    The tables have the same node counts; ``stacked`` is ``np.stack([table.flat for table in tables])``.  The phase
    and load coefficients of all contacts are one vectorised expression each (the same correctly rounded operations
    per element as :meth:`~CorrugationTable.evaluate`'s, ``np.sin`` included, elementwise), the creep coefficients
    :func:`~rollcontact.stepping.line.tabulation.coefficient_rows`; the scalar parts (the load's logarithm, the phase,
    the units) are :meth:`~CorrugationTable.evaluate`'s Python float operations, contact by contact.  A contact whose
    phase or load coordinate is at an end or on a node, and a lone contact, are evaluated alone.
    """
    answers: list = [None] * len(tables)
    batch, thetas, ells = [], [], []
    for i, (table, x, load, creep) in enumerate(zip(tables, xs, loads, creeps, strict=True)):
        ell = (math.log(load) - table.log_low) / table.log_span
        theta = (x * table.wavenumber) % TWO_PI
        if (len(tables) > 1 and 1e-13 < ell < 1.0 - 1e-13 and 1e-13 < theta < TWO_PI - 1e-13
                and ell not in table.node_set and theta not in table.node_set):
            batch.append(i)
            thetas.append(theta)
            ells.append(ell)
        else:
            answers[i] = table.evaluate(x, load, creep)
    if not batch:
        return answers
    first = tables[batch[0]]
    in_theta = contract(stacked if len(batch) == len(tables) else stacked[batch],
                        first.theta_signs / np.sin(0.5 * np.array(thetas)[:, None] - first.half_nodes))
    rows = contract(in_theta.reshape(len(batch), -1, first.l_nodes.size),
                    first.l_weights / (np.array(ells)[:, None] - first.l_nodes))
    partial, t_points, normals = [], [], {}
    for k, (i, values) in enumerate(zip(batch, rows[:, :NORMAL].tolist(), strict=True)):
        normals[k] = normal = tables[i].normal(values, loads[i], creeps[i])
        if normal[5] >= 1.0:
            answers[i] = CorrugationTable.answer(normal, creeps[i])
        else:
            partial.append(k)
            t_points.append(normal[5])
    if partial:
        blocks = rows[:, NORMAL:] if len(partial) == len(batch) else rows[partial, NORMAL:]
        coefficients = coefficient_rows(t_points, first.t_nodes, first.t_weights, first.node_set)
        for k, products in zip(partial, contract(blocks.reshape(len(partial), 4, -1), coefficients).tolist(),
                               strict=True):
            answers[batch[k]] = CorrugationTable.answer(normals[k], creeps[batch[k]], products)
    return answers
