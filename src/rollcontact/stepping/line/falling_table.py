"""The certified table of falling friction on a flat surface (used by :mod:`rollcontact.stepping.line.table`).

With the exponential law ``mu(v) = mu_s [(1 - A) exp(-B v) + A]`` on a flat surface, the steady problem scales with
the Hertz half-width a: slip, traction and the slip velocities all scale with Carter's saturation creep
``xi_sat = mu_s a / R``.  The normalised force ``tau = T'/(mu_s N')``, the stick fraction ``a*/a`` and the normalised
creep stiffness ``kappa = (dT'/dxi) xi_sat / (mu_s N')`` are therefore functions of two numbers only,

    ``u = |xi| / xi_sat``  and  ``w = B V xi_sat``,

for a given kinetic ratio A (``tests/stepping/test_falling_table.py`` checks the scaling against the exact solver to
round-off).  :class:`FallingFrictionTable` interpolates them over ``0 <= w <= w_max`` and every ``u >= 0``
(T' is odd in the creep, a* and the stiffness even):

* the onset of full slip ``u_fs(w)`` (where the stick zone vanishes) is found per w node and interpolated;
* partial slip, ``t = u/u_fs in [0, 1]``, and full slip, ``r = u_fs/u in (0, 1]``, are separate tensor grids of
  Chebyshev points (second kind, with their ends) in (t, w) and (r, w): the kink of the creep curve at the onset is
  an edge of both, not inside either, so the barycentric interpolation converges fast on each;
* in full slip the tables hold the difference to the asymptote of deep slip, ``tau -> (1 - A) exp(-w u) + A`` (the
  slip velocity approaches ``V xi`` everywhere), which is exact at ``r = 0`` (no solve there).

The nodes are solved by the polynomial method (``rollcontact.solve(..., tolerance=NODE_TOLERANCE)``, within
:data:`NODE_NODES` nodes and :data:`NODE_ITERATIONS` steps).  The table is certified a posteriori: the exact solution
at the midpoints between nodes (in t or r and in w) is compared with the interpolant, and the bound the table reports
is ``2 max|difference| + the nodes' largest error estimate`` [1 of mu_s N']; while it exceeds the target the node
counts grow (a table whose nodes' estimates alone take half the target is given up).  Outside its domain
(w beyond ``w_max``) the step solves exactly.
"""

from __future__ import annotations

import math

import numpy as np

from rollcontact.core.friction import ExponentialFalling
from rollcontact.core.materials import Material
from rollcontact.line.dispatch import METHODS, solve
from rollcontact.line.hertz import hertz
from rollcontact.line.scene import Scene
from rollcontact.stepping.line.tabulation import (
    MAX_NODES,
    NODE_TOLERANCE,
    TARGET,
    CertifiedTable,
    Node,
    barycentric_weights,
    basis,
    chebyshev_points,
    coefficient_rows,
    contract,
    onset,
)

NODES = (9, 13, 9)
"""Starting node counts in w, in t (partial slip) and in r (full slip); doubled (less one) while the check fails."""

EXPECTED_SOLVES = 600
"""Exact solves a build is modelled to take (its nodes, their onsets and the check; ``benchmarks/bench_table.py``
reports the count)."""

SOLVE_COST = 2e-3
"""Modelled time [s] of one exact solve of a build: about the mean of a build's solves over the kinetic ratios
(``benchmarks/bench_table.py``, "Builds", seconds over solves), with which ``table`` = auto spreads a build over the
exact steps."""

NODE_NODES = 256
"""Largest slip-iteration node count of a node's solve: its escalation stops there (the modelled budget of the solve
admits the ladder's counts up to it), so no node costs the seconds of 512 nodes; the node's a-posteriori
estimate, which enters the table's bound, says what that leaves."""

NODE_ITERATIONS = 200
"""Largest number of slip-iteration steps of a node's solve (Newton, and as many of the relaxed fixed point, which
near the onset of full slip at large w needs about a hundred): a node that does not converge within them gives the
table up rather than run on."""

W_LIMIT = 5.0
"""Largest ``w_max`` a table is built for, at any kinetic ratio (:func:`w_limit`)."""

FALL_LIMIT = 0.8
"""Largest ``(1 - A) w_max``, the fall of the friction coefficient over the saturation slip (in units of mu_s),
a table is built for (:func:`w_limit`).  Beyond it the nodes' slip iterations need more than :data:`NODE_NODES`
nodes to meet :data:`~rollcontact.stepping.line.tabulation.NODE_TOLERANCE`, or more than :data:`NODE_ITERATIONS` steps
to converge, and the table would miss its target or take tens of seconds (``benchmarks/bench_table.py``, "Largest
domains", builds at every kinetic ratio within the limit)."""


def w_limit(kinetic_ratio: float) -> float:
    """Largest ``w_max`` [1] of a table of the kinetic ratio A: ``min(W_LIMIT, FALL_LIMIT / (1 - A))``; steps beyond
    it solve exactly."""
    fall = 1.0 - kinetic_ratio
    return W_LIMIT if fall * W_LIMIT <= FALL_LIMIT else FALL_LIMIT / fall

REFERENCE_LOAD = 1e6
"""N' [N/m] of the normalised scenes the nodes are solved on (any load gives the same normalised answer)."""


class FallingFrictionTable(CertifiedTable):
    """tau, a*/a and kappa of the exponential falling law on a flat surface, interpolated over (u, w) (module
    docstring).

    Parameters
    ----------
    kinetic_ratio : float
        A of the law, in (0, 1].
    w_max : float
        Largest ``B V xi_sat`` [1] the table covers.
    material, radius, static_coefficient
        Of the normalised scenes; the answer does not depend on them (the scaling), only their consistency does.

    Attributes
    ----------
    bound : float
        Certified error of tau [1 of mu_s N'] (NaN until built).
    solves : int
        Exact solves it took.
    """

    max_solves = 10 * EXPECTED_SOLVES

    def __init__(self, kinetic_ratio: float, w_max: float, material: Material | None = None, radius: float = 0.46,
                 static_coefficient: float = 0.3):
        self.kinetic_ratio = float(kinetic_ratio)
        self.w_max = float(w_max)
        self.material = Material() if material is None else material
        self.radius = float(radius)
        self.mu = float(static_coefficient)
        a = hertz(REFERENCE_LOAD, self.radius, self.material.contact_modulus)[0]
        self.saturation = self.mu * a / self.radius
        self.bound = math.nan
        self.solves = 0
        self.ready = False

    @property
    def domain(self) -> tuple[float]:
        """``(w_max,)``: what, with the parameters, determines the table."""
        return (self.w_max,)

    @property
    def nbytes(self) -> int:
        """Size of the interpolation data [bytes]."""
        return sum(a.nbytes for a in (self.rows, self.w_unit, self.t_nodes, self.r_nodes))

    # ---------------------------------------------------------------------------------------------- exact nodes
    def exact(self, u: float, w: float) -> Node:
        """The normalised solution at (u, w) by the polynomial method (one solve)."""
        speed = w / self.saturation  # B = 1 s/m
        scene = Scene(REFERENCE_LOAD, creep=u * self.saturation, radius=self.radius, material=self.material,
                      friction=ExponentialFalling(self.mu, self.kinetic_ratio, 1.0), rolling_speed=speed)
        model = METHODS["polynomial"].accuracy
        budget = sum(model.cost(scene, o) for o in model.ladder(scene) if o.get("nodes", 0) <= NODE_NODES)
        result = solve(scene, method="polynomial", tolerance=NODE_TOLERANCE, budget=budget,
                       slip_iterations=NODE_ITERATIONS)
        self.solves += 1
        if not result.success:
            raise ArithmeticError(f"table node u = {u:.6g}, w = {w:.6g}: {result.message}")
        limit = self.mu * REFERENCE_LOAD
        a = hertz(REFERENCE_LOAD, self.radius, self.material.contact_modulus)[0]
        return Node(result.tangential_force_per_length / limit, result.stick_half_width / a,
                    result.creep_stiffness_per_length * self.saturation / limit,
                    float(result.info.get("error_estimate", 0.0)))

    def onset(self, w: float):
        """u of the onset of full slip at w (a build-step generator,
        :func:`~rollcontact.stepping.line.tabulation.onset`)."""
        return (yield from onset(lambda u: self.node(u, w)))

    # ------------------------------------------------------------------------------------------------- build
    def build_steps(self):
        """Solve the nodes, check the midpoints, refine until the check meets :data:`TARGET`, one exact solve per
        iteration (a caller can spread the build over many steps); ready at the end.

        Raises
        ------
        ArithmeticError
            A node the exact solver cannot solve, :data:`MAX_NODES` reached without meeting the target, or the
            nodes' own error estimates leaving a bound above the target.
        """
        n_w, n_t, n_r = NODES
        while True:
            yield from self.tabulate(n_w, n_t, n_r)
            error = yield from self.check()
            if 2.0 * error + self.node_error <= TARGET:
                self.bound = 2.0 * error + self.node_error
                self.ready = True
                return
            if self.node_error >= 0.5 * TARGET:
                raise ArithmeticError(f"the nodes' error estimates ({self.node_error:.3g} mu N) leave no room for "
                                      f"the table's bound of {TARGET:g} mu N")
            if max(n_w, n_t, n_r) * 2 - 1 > MAX_NODES:
                raise ArithmeticError(f"the table does not meet {TARGET:g} mu N with {MAX_NODES} nodes per "
                                      f"direction (check error {error:.3g})")
            n_w, n_t, n_r = 2 * n_w - 1, 2 * n_t - 1, 2 * n_r - 1

    def tabulate(self, n_w: int, n_t: int, n_r: int):
        """The nodes (a build step generator): the onset per w node, partial slip on (t, w), full slip on (r, w) as
        the difference to the deep-slip asymptote (zero at r = 0, not solved)."""
        w_nodes = self.w_max * chebyshev_points(n_w)
        t_nodes, r_nodes = chebyshev_points(n_t), chebyshev_points(n_r)
        onsets = []
        for w in w_nodes:
            onsets.append((yield from self.onset(w)))
        partial = np.zeros((3, n_t, n_w))
        full = np.zeros((2, n_r, n_w))
        estimates = [0.0]
        for j, (w, u_fs) in enumerate(zip(w_nodes, onsets, strict=True)):
            for i, t in enumerate(t_nodes):
                node = yield from self.node(t * u_fs, w)
                partial[:, i, j] = node.tau, node.alpha, node.kappa
                estimates.append(node.estimate * abs(node.tau))
            for i, r in enumerate(r_nodes[1:], start=1):
                u = u_fs / r
                node = yield from self.node(u, w)
                tau, kappa = self.asymptote(u, w)
                full[:, i, j] = node.tau - tau, node.kappa - kappa
                estimates.append(node.estimate * abs(node.tau))
        self.w_nodes, self.t_nodes, self.r_nodes = w_nodes, t_nodes, r_nodes
        self.w_unit = chebyshev_points(n_w)  # w / w_max at the nodes
        self.node_set = {*self.w_unit.tolist(), *t_nodes.tolist(), *r_nodes.tolist()}
        self.w_weights, self.t_weights, self.r_weights = (barycentric_weights(n) for n in (n_w, n_t, n_r))
        self.onsets, self.partial, self.full = np.array(onsets), partial, full
        ones = lambda n: np.ones((1, n, n_w))  # noqa: E731 - a one-line helper
        self.rows = np.vstack((self.onsets[None], np.concatenate((partial, ones(n_t))).reshape(-1, n_w),
                               np.concatenate((full, ones(n_r))).reshape(-1, n_w)))
        self.node_error = max(estimates)

    def check(self):
        """Largest |tau - exact| [1 of mu_s N'] at the midpoints between the nodes, in t or r and in w (a build step
        generator)."""
        mid = lambda x: 0.5 * (x[1:] + x[:-1])  # noqa: E731 - a one-line helper
        error = 0.0
        for w in np.concatenate((mid(self.w_nodes), self.w_nodes[[0, -1]])):
            u_fs = self.onset_at(w)
            for u in np.concatenate((mid(self.t_nodes) * u_fs, u_fs / mid(self.r_nodes))):
                node = yield from self.node(u, w)
                error = max(error, abs(self.evaluate(u, w)[0] - node.tau))
        return error

    def asymptote(self, u: float, w: float) -> tuple[float, float]:
        """tau and kappa of deep full slip: ``(1 - A) exp(-w u) + A`` and its u-derivative."""
        decay = (1.0 - self.kinetic_ratio) * math.exp(-w * u)
        return decay + self.kinetic_ratio, -w * decay

    # ---------------------------------------------------------------------------------------------- evaluate
    def onset_at(self, w: float) -> float:
        """u_fs(w), interpolated."""
        return float(basis(w / self.w_max, self.w_unit, self.w_weights) @ self.onsets)

    def evaluate(self, u: float, w: float) -> tuple[float, float, float] | None:
        """(tau, a*/a, kappa) at u >= 0 and w, or None outside the domain (w beyond w_max).

        One contraction in w of all the tables at once (``rows``: the onsets; tau, a*/a, kappa and ones per t node;
        the differences of tau and kappa and ones per r node), then one in t or r; the ones rows carry the
        barycentric sums, so the interpolants are normalised once, on the scalars.  A coordinate at the ends or equal
        to a node (of any direction: a set lookup) takes the general path.
        """
        if not 0.0 <= w <= self.w_max:
            return None
        x = w / self.w_max
        if 1e-13 < x < 1.0 - 1e-13 and x not in self.node_set:
            values = self.rows @ (self.w_weights / (x - self.w_unit))
        else:
            values = self.rows @ basis(x, self.w_unit, self.w_weights)
        split = 1 + 4 * self.t_nodes.size
        u_fs = float(values[0] / values[split - 1])
        if u <= u_fs:
            t = u / u_fs
            if 1e-13 < t < 1.0 - 1e-13 and t not in self.node_set:
                coefficients = self.t_weights / (t - self.t_nodes)
            else:
                coefficients = basis(t, self.t_nodes, self.t_weights)
            tau, alpha, kappa, scale = (values[1:split].reshape(4, -1) @ coefficients).tolist()
            return tau / scale, alpha / scale, kappa / scale
        r = u_fs / u
        if 1e-13 < r < 1.0 - 1e-13 and r not in self.node_set:
            coefficients = self.r_weights / (r - self.r_nodes)
        else:
            coefficients = basis(r, self.r_nodes, self.r_weights)
        d_tau, d_kappa, scale = (values[split:].reshape(3, -1) @ coefficients).tolist()
        tau, kappa = self.asymptote(u, w)
        return tau + d_tau / scale, 0.0, kappa + d_kappa / scale


def evaluate_together(tables: list[FallingFrictionTable], stacked: np.ndarray, us: list[float],
                      ws: list[float]) -> list[tuple[float, float, float] | None]:
    """:meth:`FallingFrictionTable.evaluate` of each of ``tables`` at its ``(u, w)``, bit for bit, with each
    contraction of all of them in one stacked matrix product (:func:`~rollcontact.stepping.line.tabulation.contract`).

    The tables have the same node counts; ``stacked`` is ``np.stack([table.rows for table in tables])``.  The
    coefficients are :func:`~rollcontact.stepping.line.tabulation.coefficient_rows` (a coordinate at an end or on a node
    takes the general path's :func:`~rollcontact.stepping.line.tabulation.basis`, as in
    :meth:`~FallingFrictionTable.evaluate`); the scalar tails (the normalisation, the asymptote's exp) are
    :meth:`~FallingFrictionTable.evaluate`'s Python float operations, contact by contact.  One table, whose numpy
    calls cost more than its products, is evaluated alone.
    """
    if len(tables) == 1:
        return [tables[0].evaluate(us[0], ws[0])]
    if not all(0.0 <= w <= table.w_max for table, w in zip(tables, ws, strict=True)):  # None outside the domain
        inside = [i for i, (table, w) in enumerate(zip(tables, ws, strict=True)) if 0.0 <= w <= table.w_max]
        answers = [None] * len(tables)
        if inside:
            for i, answer in zip(inside, evaluate_together([tables[i] for i in inside], stacked[inside],
                                                           [us[i] for i in inside], [ws[i] for i in inside]),
                                 strict=True):
                answers[i] = answer
        return answers
    first = tables[0]
    values = contract(stacked, coefficient_rows([w / table.w_max for table, w in zip(tables, ws, strict=True)],
                                                first.w_unit, first.w_weights, first.node_set))
    split = 1 + 4 * first.t_nodes.size
    onsets = (values[:, 0] / values[:, split - 1]).tolist()
    partial = [i for i, (u, u_fs) in enumerate(zip(us, onsets, strict=True)) if u <= u_fs]
    answers: list = [None] * len(tables)
    if partial:
        blocks = values[:, 1:split] if len(partial) == len(tables) else values[partial, 1:split]
        rows = coefficient_rows([us[i] / onsets[i] for i in partial], first.t_nodes, first.t_weights, first.node_set)
        for i, (tau, alpha, kappa, scale) in zip(partial, contract(blocks.reshape(len(partial), 4, -1), rows).tolist(),
                                                 strict=True):
            answers[i] = (tau / scale, alpha / scale, kappa / scale)
    if len(partial) < len(tables):
        full = [i for i, (u, u_fs) in enumerate(zip(us, onsets, strict=True)) if not u <= u_fs]
        blocks = values[full, split:].reshape(len(full), 3, -1)
        rows = coefficient_rows([onsets[i] / us[i] for i in full], first.r_nodes, first.r_weights, first.node_set)
        for i, (d_tau, d_kappa, scale) in zip(full, contract(blocks, rows).tolist(), strict=True):
            tau, kappa = tables[i].asymptote(us[i], ws[i])
            answers[i] = (tau + d_tau / scale, 0.0, kappa + d_kappa / scale)
    return answers
