"""The certified table of the elliptic strips (used by :mod:`rollcontact.stepping.elliptic.model`): the strips'
normalised forces over a/b and three normalised creepages, built once per Poisson's ratio, answered in a few
microseconds per contact.

Similarity
----------
With Coulomb friction the strips' forces of a contact (:mod:`rollcontact.elliptic.methods.strips`), normalised as

    ``tau_x = Fx / (mu Fn)``,  ``tau_y = Fy / (mu Fn)``,  ``tau_z = Mz / (mu Fn c)``,

depend on a/b, nu and the three normalised creepages

    ``u_x = G c^2 C11 xi / (mu Fn)``,  ``u_y = G c^2 C22 eta / (mu Fn)``,
    ``u_s = G c^2 (C23 c + C11 b / 2) phi / (mu Fn)``

alone (G the shear modulus, c = sqrt(ab), C_ij Kalker's coefficients at a/b and nu): every quantity of a strip (its
rigid slip in units of ``a / (2 mu p0)``, the scaled spin, the march's flexibilities over the cells, the stick zones,
the cross influence) is such a function, since Hertz's ``p0 = 3 Fn / (2 pi a b)`` ties the load to the ellipse.  u_x
and u_y are the linear theory's forces over mu Fn; u_s counts both slips of spin, the lateral ``phi x`` (the linear
theory's lateral force of spin, ``G c^3 C23 phi``) and the longitudinal ``-phi y``, which at small a/b (``b >> a``)
saturates the strips long before the lateral one (the longitudinal creepage ``phi b / 2`` in units of u_x).
``tests/stepping/elliptic/test_table.py`` checks the similarity against the strips to rounding.

Symmetries (exact in Kalker's theory and the strips, whose strips lie symmetrically in y): reversing every creepage
reverses every force, and the mirror ``y -> -y`` takes ``(xi, eta, phi)`` to ``(xi, -eta, -phi)`` and ``(Fx, Fy, Mz)``
to ``(Fx, -Fy, -Mz)``.  So the table holds ``u_x >= 0``, ``u_y >= 0`` and either sign of ``u_s``.

Coordinates
-----------
Four coordinates map the unbounded creepages onto a box: ``rho = ln(a/b)`` over Kalker's table
(:func:`~rollcontact.elliptic.creep_coefficients.aspect_ratio_range`), and, with ``R = |(u_x, u_y)|``,
``S = |u_s|``,

    ``sigma = sign(u_s) S / (S + SPIN_SCALE)`` in [-1, 1],  ``q = R / (R + CREEP_SCALE + CREEP_SPIN_SCALE S)`` in
    [0, 1],  ``alpha = atan2(u_y, u_x)`` in [0, pi/2].

``sigma = +-1`` and ``q = 1`` are unbounded spin and creep, where the strips slip fully along the rigid slip: the nodes
there are solved at :data:`FAR` in these coordinates.  q measures the creep against the spin, so that with both large
the forces are a smooth function of their ratio.  Two features of the strips are kept out of the interpolation:

* at ``u_s = 0`` the strips take the lateral force's cross influence and no march, and with any spin the march and no
  cross influence, so the forces jump there; the spin table is split at ``sigma = 0`` into two halves whose node
  ``sigma = 0`` holds the limit of vanishing spin (solved at :data:`TINY_SPIN`), and steps without spin take a table
  of their own over ``(rho, q0, alpha)``, ``q0 = R / (R + CREEP_SCALE)``;
* the spin's flexibility factors depend on ``|u_s|`` (a kink at 0), which the split also keeps at an end.

Interpolation
-------------
Tensor-product cubic Hermite interpolation on uniform nodes with Catmull-Rom slopes (the central difference; one-sided
of second order at the ends, by a ghost node ``3 f_0 - 3 f_1 + f_2`` beyond each end), continuous with its first
derivatives inside each table.  On a cell of width h, ``s = (x - x_j) / h``, the weights of ``f_(j-1) .. f_(j+2)`` are

    ``((-s + 2 s^2 - s^3), (2 - 5 s^2 + 3 s^3), (s + 4 s^2 - 3 s^3), (s^3 - s^2)) / 2``

(E. Catmull, R. Rom, "A class of local interpolating splines", 1974).  A step's forces contract 4^4 nodes (4^3 without
spin) with the products of these weights; its Jacobian (``jacobian`` = difference) the same nodes with one weight
replaced by its derivative, through the chain rule of the coordinates.  The weights are Python floats, the contraction
a few small matrix products, one axis after the other (:meth:`Grid.value`): a contact's answer is a function of its
own arguments, the same whatever the other contacts of the step.

Certificate
-----------
The nodes are the strips' solves (their defaults, in batches of :data:`CHUNK` scenes, one BLAS thread).  The check
solves the strips at the centre of every cell of every table (the point farthest from its nodes) and compares the
interpolant; the table's bound is :data:`BOUND_FACTOR` times the largest difference of ``tau_x``, ``tau_y`` and
``tau_z``, an error against the strips, in units of mu Fn (mu Fn c for Mz).  The error against Kalker's exact theory is
that bound plus the strips' own (their accuracy model).  A table is a deterministic function of its Poisson's ratio
and node counts (no clock, no randomness): a build repeats bit for bit, and the tables of a process are kept per key
(:func:`cached_table`).  Its work is its solves, known before it starts (:meth:`EllipticTable.solves_planned`),
modelled at :data:`SOLVE_COST` each.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np

from rollcontact.core.friction import Coulomb
from rollcontact.core.materials import Material
from rollcontact.elliptic.creep_coefficients import aspect_ratio_range, creepage_coefficients
from rollcontact.elliptic.hertz import curvatures_from_semi_axes
from rollcontact.elliptic.methods.strips import solve_strips_many
from rollcontact.elliptic.scene import EllipticScene
from rollcontact.stepping.threads import one_blas_thread

__all__ = ["EllipticTable", "TableAnswer", "cached_table"]

SPIN_SCALE = 4.0
"""``S0`` [1]: the normalised spin at ``sigma = 1/2`` (the strips' spin effects lie within a few S0)."""

CREEP_SCALE = 2.0
"""``C0`` [1]: the normalised creep at ``q = 1/2`` without spin (about the strips' full slip)."""

CREEP_SPIN_SCALE = 1.0
"""``C1`` [1]: the normalised creep per unit of normalised spin at ``q = 1/2``."""

NODES = (9, 33, 25, 13)
"""Node counts in rho, q, sigma (each half, ``sigma = 0`` included) and alpha of the spin tables; the table without
spin takes those of rho, q0 and alpha."""

FAR = 1.0 - 1e-9
"""Where ``q = 1`` and ``|sigma| = 1`` (unbounded creep and spin) are solved: creep 1e9 times its scale."""

TINY_SPIN = 1e-9
"""``u_s`` [1] of the nodes at ``sigma = 0`` in the spin tables: the limit of vanishing spin (its forces differ from
the limit by about that much)."""

CHUNK = 32
"""Scenes per :func:`~rollcontact.elliptic.methods.strips.solve_strips_many` call of a build."""

SOLVE_COST = 6e-5
"""Modelled time [s] of one scene of a build (``benchmarks/bench_elliptic_table.py``, "Build": seconds over solves,
the scene's strips with spin in a batch of :data:`CHUNK` and its scene made from its node's)."""

BOUND_FACTOR = 1.5
"""The table's bound over the largest difference at the cells' centres: the audit at random points not on the
check's (``benchmarks/bench_elliptic_table.py``, "Audit") finds its largest error within the bound."""

TARGET = 0.01
"""The bound [1 of mu Fn] a table aims at (the FMU's real-time aim); the bound reached is reported either way."""

REFERENCE = {"normal_load": 1e5, "semi_axis": 5e-3, "youngs_modulus": 210e9, "friction_coefficient": 0.3}
"""The scenes the nodes are solved on (any other gives the same normalised forces: the similarity)."""


class Axis:
    """Uniform nodes ``lo .. hi`` (n of them) of one coordinate, and where a point lies among them."""

    def __init__(self, lo: float, hi: float, n: int):
        if n < 3:
            raise ValueError(f"an axis of the table needs at least 3 nodes, got {n}")
        self.lo, self.hi, self.n = float(lo), float(hi), int(n)
        self.h = (self.hi - self.lo) / (self.n - 1)
        self.inv_h = 1.0 / self.h
        self.nodes = self.lo + self.h * np.arange(self.n)
        self.nodes[-1] = self.hi

    @property
    def centres(self) -> np.ndarray:
        """The midpoints of the cells."""
        return 0.5 * (self.nodes[1:] + self.nodes[:-1])


def catmull_rom(s: float) -> tuple[float, float, float, float]:
    """The Catmull-Rom weights of the four nodes ``j - 1 .. j + 2`` at ``s`` in [0, 1] of cell j (module
    docstring)."""
    s2 = s * s
    s3 = s2 * s
    return (0.5 * (2.0 * s2 - s - s3), 0.5 * (2.0 - 5.0 * s2 + 3.0 * s3), 0.5 * (s + 4.0 * s2 - 3.0 * s3),
            0.5 * (s3 - s2))


def catmull_rom_slopes(s: float, inv_h: float) -> tuple[float, float, float, float]:
    """The derivatives of :func:`catmull_rom`'s weights in the coordinate (``inv_h`` = 1/h)."""
    s2 = s * s
    f = 0.5 * inv_h
    return (f * (4.0 * s - 1.0 - 3.0 * s2), f * (9.0 * s2 - 10.0 * s), f * (1.0 + 8.0 * s - 9.0 * s2),
            f * (3.0 * s2 - 2.0 * s))


def padded(values: np.ndarray, dims: int) -> np.ndarray:
    """``values`` (nodes along the first ``dims`` axes, components last) with a ghost node beyond each end of each
    axis, ``3 f_0 - 3 f_1 + f_2``: the Catmull-Rom slope at an end becomes the one-sided difference of second order."""
    for axis in range(dims):
        v = np.moveaxis(values, axis, 0)
        values = np.moveaxis(np.concatenate((3.0 * v[:1] - 3.0 * v[1:2] + v[2:3], v,
                                             3.0 * v[-1:] - 3.0 * v[-2:-1] + v[-3:-2])), 0, axis)
    return np.ascontiguousarray(values)


class Grid:
    """One table: its axes and its padded node values (components last)."""

    def __init__(self, axes: tuple[Axis, ...], values: np.ndarray):
        self.axes = axes
        self.dims = len(axes)
        self.data = padded(values, self.dims)

    def value(self, point, derivatives: bool) -> list:
        """The interpolant at ``point`` (a coordinate tuple): ``[values]`` (the components), with ``derivatives``
        followed by its derivatives in each axis but the first (rho), each a list of the components.

        The stencil of 4^d padded nodes is contracted one axis after the other (rho first) with its weights, and with
        ``derivatives`` at once with their derivatives (a ``(2, 4)`` matrix per axis): a few small matrix products,
        the same for every point, so a point's numbers are those of any other call."""
        starts, weights = [], []
        for x, axis in zip(point, self.axes, strict=True):
            z = (x - axis.lo) * axis.inv_h
            j = int(z)
            if j > axis.n - 2:
                j = axis.n - 2
            elif j < 0:
                j = 0
            starts.append(j)
            weights.append((catmull_rom(z - j), catmull_rom_slopes(z - j, axis.inv_h)) if derivatives
                           else catmull_rom(z - j))
        j0, j1, j2 = starts[:3]
        if self.dims == 4:
            j3 = starts[3]
            block = self.data[j0:j0 + 4, j1:j1 + 4, j2:j2 + 4, j3:j3 + 4]
        else:
            block = self.data[j0:j0 + 4, j1:j1 + 4, j2:j2 + 4]
        factors = np.array(weights)  # (d, 4), or (d, 2, 4) with the derivatives
        values = (factors[0, 0] if derivatives else factors[0]) @ block.reshape(4, -1)
        if not derivatives:
            for w in factors[1:]:
                values = w @ values.reshape(4, -1)
            return [values.tolist()]
        for pair in factors[1:]:  # (..., 4 nodes, rest) -> (..., 2, rest): this axis's value and derivative
            values = pair @ values.reshape(*values.shape[:-1], 4, -1)
        out = values.reshape(-1, values.shape[-1]).tolist()  # rows: the axes' (value, derivative), first slowest
        count = self.dims - 1
        return [out[0], *(out[1 << (count - 1 - k)] for k in range(count))]


class TableAnswer(tuple):
    """``(tau_x, tau_y, tau_z, jacobian)``: the normalised forces (module docstring) and, when asked for, their
    derivatives ``d(tau_x, tau_y, tau_z)/d(u_x, u_y, u_s)`` row by row (9 floats), else None."""

    __slots__ = ()


def coordinates(ux: float, uy: float, us: float) -> tuple:
    """The reduced creepages and the table's coordinates of ``(u_x, u_y, u_s)``: ``(sign, mirror, R, S, spin sign,
    q or q0, sigma, alpha)`` (module docstring); sign -1 reverses every force, mirror -1 the lateral force and the
    moment."""
    sign = -1.0 if ux < 0.0 else 1.0
    ux, uy, us = sign * ux, sign * uy, sign * us
    mirror = -1.0 if uy < 0.0 else 1.0
    uy, us = mirror * uy, mirror * us
    r = math.hypot(ux, uy)
    s = abs(us)
    spin = -1.0 if us < 0.0 else 1.0
    alpha = math.atan2(uy, ux) if r > 0.0 else 0.0
    if s == 0.0:
        return sign, mirror, r, s, spin, r / (r + CREEP_SCALE), 0.0, alpha
    return sign, mirror, r, s, spin, r / (r + CREEP_SCALE + CREEP_SPIN_SCALE * s), spin * s / (s + SPIN_SCALE), alpha


class EllipticTable:
    """The strips' normalised forces of one Poisson's ratio over a/b and the creepages (module docstring).

    Parameters
    ----------
    poisson_ratio : float
        nu of the contacts, in [0, 0.5).
    nodes : tuple of int
        Node counts in rho, q, sigma (each half) and alpha (:data:`NODES`; small ones for tests).

    Attributes
    ----------
    bound : float
        Certified error [1 of mu Fn] against the strips (NaN until built).
    check_error : tuple of float
        The largest differences at the cells' centres of tau_x, tau_y and tau_z, with spin and without.
    solves : int
        Strips solves the build took.
    """

    def __init__(self, poisson_ratio: float, nodes: tuple[int, int, int, int] = NODES):
        self.poisson_ratio = float(poisson_ratio)
        self.nodes = tuple(int(n) for n in nodes)
        low, high = aspect_ratio_range()
        n_rho, n_q, n_sigma, n_alpha = self.nodes
        self.rho = Axis(math.log(low), math.log(high), n_rho)
        self.q = Axis(0.0, 1.0, n_q)
        self.negative_sigma = Axis(-1.0, 0.0, n_sigma)
        self.positive_sigma = Axis(0.0, 1.0, n_sigma)
        self.alpha = Axis(0.0, 0.5 * math.pi, n_alpha)
        self.material = Material(REFERENCE["youngs_modulus"], self.poisson_ratio)
        self.shear_modulus = self.material.shear_modulus
        self.bound = math.nan
        self.check_error: tuple[float, ...] = ()
        self.solves = 0
        self.ready = False
        self.tables: dict[str, Grid] = {}

    @property
    def key(self) -> tuple:
        """What determines the table: Poisson's ratio and node counts."""
        return (self.poisson_ratio, self.nodes)

    def solves_planned(self) -> int:
        """The strips solves a build takes: the nodes of every table and the centres of their cells."""
        n_rho, n_q, n_sigma, n_alpha = self.nodes
        spin = n_rho * n_q * (2 * n_sigma - 1) * n_alpha + (n_rho - 1) * (n_q - 1) * 2 * (n_sigma - 1) * (n_alpha - 1)
        plain = n_rho * n_q * n_alpha + (n_rho - 1) * (n_q - 1) * (n_alpha - 1)
        return spin + plain

    def batch_sizes(self) -> list[int]:
        """The solves of each batch of a build, in its order (:meth:`build_steps` yields once per batch)."""
        n_rho, n_q, n_sigma, n_alpha = self.nodes
        groups = [n_q * (2 * n_sigma - 1) * n_alpha, n_q * n_alpha] * n_rho + \
            [(n_q - 1) * 2 * (n_sigma - 1) * (n_alpha - 1), (n_q - 1) * (n_alpha - 1)] * (n_rho - 1)
        return [min(CHUNK, size - start) for size in groups for start in range(0, size, CHUNK)]

    @property
    def nbytes(self) -> int:
        """Size of the interpolation data [bytes]."""
        return sum(grid.data.nbytes for grid in self.tables.values())

    # ----------------------------------------------------------------------------------------------- solving
    @cached_property
    def bases(self) -> list[tuple[EllipticScene, tuple[float, float, float, float]]]:
        """Per rho node: the scene of that a/b at the reference load (its Hertz ellipse computed) and the factors
        ``(xi, eta, phi)`` per unit of ``(u_x, u_y, u_s)`` and ``c``."""
        load, b, mu = REFERENCE["normal_load"], REFERENCE["semi_axis"], REFERENCE["friction_coefficient"]
        out = []
        for rho in self.rho.nodes:
            A, B = curvatures_from_semi_axes(b * math.exp(rho), b, load, self.material.contact_modulus)
            scene = EllipticScene(load, A, B, material=self.material, friction=Coulomb(mu))
            out.append((scene, self.factors(scene)))
        return out

    def factors(self, scene: EllipticScene) -> tuple[float, float, float, float]:
        """``(xi, eta, phi)`` per unit of ``(u_x, u_y, u_s)`` at the scene's ellipse, and c [m]."""
        h = scene.hertz
        c = creepage_coefficients(h.aspect_ratio, self.poisson_ratio)
        scale = scene.friction_coefficient * scene.normal_load / (self.shear_modulus * h.c * h.c)
        return scale / c.c11, scale / c.c22, scale / (c.c23 * h.c + 0.5 * c.c11 * h.b), h.c

    def base_at(self, rho: float) -> tuple[EllipticScene, tuple[float, float, float, float]]:
        """The scene of a/b = exp(rho) at the reference load and its factors (:attr:`bases` for a node's rho)."""
        load, b, mu = REFERENCE["normal_load"], REFERENCE["semi_axis"], REFERENCE["friction_coefficient"]
        A, B = curvatures_from_semi_axes(b * math.exp(rho), b, load, self.material.contact_modulus)
        scene = EllipticScene(load, A, B, material=self.material, friction=Coulomb(mu))
        return scene, self.factors(scene)

    @staticmethod
    def creepages(q: float, sigma: float, alpha: float, no_spin: bool = False) -> tuple[float, float, float]:
        """``(u_x, u_y, u_s)`` at the coordinates (``no_spin``: q is q0 and u_s = 0); the ends are solved at
        :data:`FAR`, ``sigma = 0`` of a spin table at :data:`TINY_SPIN`."""
        if no_spin:
            s, scale = 0.0, CREEP_SCALE
        else:
            t = min(abs(sigma), FAR)
            s = SPIN_SCALE * t / (1.0 - t)
            scale = CREEP_SCALE + CREEP_SPIN_SCALE * s
        q = min(q, FAR)
        r = scale * q / (1.0 - q)
        us = 0.0 if no_spin else (math.copysign(s, sigma) if sigma != 0.0 else TINY_SPIN)
        return r * math.cos(alpha), r * math.sin(alpha), us

    def solve(self, points: list[tuple], base) -> list[tuple[float, float, float]]:
        """The strips' normalised forces at ``points`` ``(u_x, u_y, u_s)`` on the ellipse of ``base``
        (:attr:`bases`), in batches of :data:`CHUNK` (a build step generator: yields once per batch)."""
        scene, (fx, fy, fs, c) = base
        limit = scene.friction_coefficient * scene.normal_load
        out = []
        for start in range(0, len(points), CHUNK):
            batch = [with_creepages(scene, ux * fx, uy * fy, us * fs) for ux, uy, us in points[start:start + CHUNK]]
            with one_blas_thread():
                results = solve_strips_many(batch)
            self.solves += len(batch)
            out += [(r.longitudinal_force / limit, r.lateral_force / limit, r.spin_moment / (limit * c))
                    for r in results]
            yield len(batch)
        return out

    # ------------------------------------------------------------------------------------------------- build
    def build(self) -> EllipticTable:
        """:meth:`build_steps` to the end: ready afterwards."""
        for _ in self.build_steps():
            pass
        return self

    def build_steps(self):
        """Solve the nodes, then the cells' centres, and certify (module docstring); a generator yielding the
        number of solves of each batch (a caller may spread the build over many steps).  Ready at its end."""
        n_q, n_alpha = self.q.n, self.alpha.n
        sigmas = np.concatenate((self.negative_sigma.nodes[:-1], self.positive_sigma.nodes))
        spin = np.empty((self.rho.n, n_q, sigmas.size, n_alpha, 3))
        plain = np.empty((self.rho.n, n_q, n_alpha, 3))
        for i, base in enumerate(self.bases):
            points = [self.creepages(q, s, a) for q in self.q.nodes for s in sigmas for a in self.alpha.nodes]
            spin[i] = np.reshape((yield from self.solve(points, base)), spin.shape[1:])
            points = [self.creepages(q, 0.0, a, no_spin=True) for q in self.q.nodes for a in self.alpha.nodes]
            plain[i] = np.reshape((yield from self.solve(points, base)), plain.shape[1:])
        middle = self.positive_sigma.n - 1
        self.tables = {
            "negative": Grid((self.rho, self.q, self.negative_sigma, self.alpha), spin[:, :, :middle + 1]),
            "positive": Grid((self.rho, self.q, self.positive_sigma, self.alpha), spin[:, :, middle:]),
            "plain": Grid((self.rho, self.q, self.alpha), plain),
        }
        errors = yield from self.check()
        self.check_error = errors
        self.bound = BOUND_FACTOR * max(errors)
        self.ready = True

    def check(self):
        """The largest differences between the interpolant and the strips at the centres of every table's cells,
        tau_x, tau_y, tau_z with spin, then without (a build step generator)."""
        spin_error = np.zeros(3)
        plain_error = np.zeros(3)
        sigma_centres = np.concatenate((self.negative_sigma.centres, self.positive_sigma.centres))
        for rho in self.rho.centres:
            base = self.base_at(rho)
            coords = [(q, s, a) for q in self.q.centres for s in sigma_centres for a in self.alpha.centres]
            exact = np.array((yield from self.solve([self.creepages(*c) for c in coords], base)))
            table = self.interpolated([(rho, *c) for c in coords])
            spin_error = np.maximum(spin_error, np.abs(table - exact).max(axis=0))
            coords = [(q, a) for q in self.q.centres for a in self.alpha.centres]
            exact = np.array((yield from self.solve([self.creepages(q, 0.0, a, no_spin=True) for q, a in coords],
                                                    base)))
            grid = self.tables["plain"]
            table = np.array([grid.value((rho, q, a), False)[0] for q, a in coords])
            plain_error = np.maximum(plain_error, np.abs(table - exact).max(axis=0))
        return (*spin_error.tolist(), *plain_error.tolist())

    def interpolated(self, points: list[tuple[float, float, float, float]]) -> np.ndarray:
        """The spin tables' interpolant at ``points`` ``(rho, q, sigma, alpha)`` (sigma != 0), ``(m, 3)``."""
        positive, negative = self.tables["positive"], self.tables["negative"]
        return np.array([(positive if p[2] > 0.0 else negative).value(p, False)[0] for p in points])

    # ---------------------------------------------------------------------------------------------- answers
    def answer(self, rho: float, ux: float, uy: float, us: float, derivatives: bool) -> TableAnswer:
        """The normalised forces at ``(u_x, u_y, u_s)`` and rho = ln(a/b) within the table (module docstring),
        with ``derivatives`` also their derivatives in ``(u_x, u_y, u_s)``: a function of these numbers alone (no
        state, the same operations for every call).

        The reduction and the coordinates are Python floats, the interpolation a few small matrix products
        (:meth:`Grid.value`).  With ``derivatives``: where ``R = 0`` (no creep) the derivatives in u_x and u_y are
        those along ``alpha = 0`` and ``alpha = pi/2`` (a second lookup), and without spin the derivative in u_s is
        the one-sided one of the positive spin table at ``sigma = 0`` in the reduced creepages (the strips' forces
        have a kink and a jump there)."""
        sign, mirror, r, s, spin, q, sigma, alpha = coordinates(ux, uy, us)
        plain = s == 0.0
        grid = self.plain if plain else (self.positive if spin > 0.0 else self.negative)
        point = (rho, q, alpha) if plain else (rho, q, sigma, alpha)
        first = grid.value(point, derivatives)
        tx, ty, tz = first[0]
        turn = sign * mirror
        if not derivatives:
            return TableAnswer((sign * tx, turn * ty, turn * tz, None))
        scale = CREEP_SCALE if plain else CREEP_SCALE + CREEP_SPIN_SCALE * s
        d = r + scale
        dq_dr = scale / (d * d)
        dq = first[1]
        if r > 0.0:
            da = first[-1]
            cos, sin = math.cos(alpha), math.sin(alpha)
            du_x = [dq[i] * dq_dr * cos - da[i] * sin / r for i in range(3)]
            du_y = [dq[i] * dq_dr * sin + da[i] * cos / r for i in range(3)]
        else:
            across = grid.value((*point[:-1], 0.5 * math.pi), True)[1]
            du_x = [dq[i] * dq_dr for i in range(3)]
            du_y = [across[i] * dq_dr for i in range(3)]
        dq_ds = -r * CREEP_SPIN_SCALE / (d * d)
        if plain:
            side = self.positive.value((rho, q, 0.0, alpha), True)
            du_s = [side[1][i] * dq_ds + side[2][i] / SPIN_SCALE for i in range(3)]
        else:
            ds = SPIN_SCALE / ((s + SPIN_SCALE) * (s + SPIN_SCALE))
            du_s = [dq[i] * dq_ds * spin + first[2][i] * ds for i in range(3)]
        # back to the caller's creepages: the reversal leaves the derivatives as they are, the mirror flips u_y, u_s
        return TableAnswer((sign * tx, turn * ty, turn * tz,
                            (du_x[0], mirror * du_y[0], mirror * du_s[0],
                             mirror * du_x[1], du_y[1], du_s[1],
                             mirror * du_x[2], du_y[2], du_s[2])))

    @property
    def positive(self) -> Grid:
        return self.tables["positive"]

    @property
    def negative(self) -> Grid:
        return self.tables["negative"]

    @property
    def plain(self) -> Grid:
        return self.tables["plain"]


def with_creepages(scene: EllipticScene, xi: float, eta: float, phi: float) -> EllipticScene:
    """``scene`` with the creepages ``(xi, eta, phi)`` (finite by construction) and its Hertz ellipse, already
    computed, shared: a build makes hundreds of thousands of scenes of the same ellipse, whose validation and ellipse
    would cost more than their strips."""
    copy = object.__new__(EllipticScene)
    copy.__dict__.update(scene.__dict__)
    copy.__dict__.update(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi)
    return copy


TABLES: dict[tuple, EllipticTable] = {}
"""The tables built in this process, by :attr:`EllipticTable.key` (a table is a function of its key alone)."""


def cached_table(poisson_ratio: float, nodes: tuple[int, int, int, int] = NODES) -> EllipticTable | None:
    """The table of this key built in this process, or None."""
    return TABLES.get((float(poisson_ratio), tuple(nodes)))


def remember(table: EllipticTable) -> None:
    """Keep a ready table for the process (:func:`cached_table`)."""
    if table.ready:
        TABLES[table.key] = table
