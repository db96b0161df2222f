"""Steady 3D rolling on the discretised half-space (Kalker's exact theory): the normal problem and the stick/slip
problem on a :class:`~rollcontact.core.halfspace.surface.SurfaceGrid`.

Conventions (docs/physics.md, Elliptic contact): the wheel rolls towards +x, material enters at the leading edge
``x = +a``; ``w = (xi - phi y, eta + phi x)`` is the rigid slip of the wheel relative to the rail over V; ``q`` is
the traction the wheel exerts on the rail [Pa], so that in slip q points along the slip.  Suffixes: ``_pa``
pascals where a name would otherwise be ambiguous.

* Normal: the Hertz pressure sampled at the element centres and scaled to the load (:func:`hertz_pressure`), or
  the discretised problem ``h0 + u_z(p) / G - delta >= 0``, ``p >= 0``, complementarity, ``sum p dA = Fn``,
  solved by the constrained conjugate gradients of Polonsky & Keer (Wear 231, 1999) on the FFT operator
  (:func:`solve_normal`).
* Tangential, steady (:func:`solve_steady`): the slip ``s = w - K q / G`` with K the upwind rolling operator of
  :meth:`~rollcontact.core.halfspace.surface.SurfaceOperator.rolling`; stick ``s = 0``, ``|q| <= g``; slip
  ``q = g s/|s|`` with ``g = mu(V |s|) p``.  Both are the fixed point ``q = P_g(q + r s(q))`` of the projection
  onto the disc of radius g (r > 0 any scale; Alart & Curnier 1991), solved by semismooth Newton.  Each Newton
  step is a GMRES solve on the FFT operator, left-preconditioned on the stick elements by the causal inverse of
  ``K = D A`` (D the upwind difference, inverted by summing from the leading edge; A inverted on the padded
  periodic grid), identity on the slip elements.  Velocity-dependent friction enters the Jacobian through
  ``dg/d|s|``.  No loop per element: every step is a handful of array operations and FFTs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.fft as sfft
from scipy.sparse.linalg import LinearOperator, gmres

from rollcontact.core.friction import FrictionLaw
from rollcontact.core.halfspace.surface import SurfaceGrid, SurfaceOperator

NEWTON_ITERATIONS = 60
"""Cap of the semismooth Newton iterations of :func:`solve_steady`."""


GMRES_RESTART = 80
GMRES_CYCLES = 6
"""Krylov dimension and restart cycles of each Newton step's GMRES."""


NORMAL_ITERATIONS = 500
"""Cap of the conjugate-gradient iterations of :func:`solve_normal`."""


def ellipse_grid(a: float, b: float, elements: int | tuple[int, int], margin: int = 0) -> SurfaceGrid:
    """Grid of ``nx x ny`` elements across the ellipse's ``2a x 2b`` [m], plus ``margin`` elements on each side.

    Element edges fall on ``x = +-a`` and ``y = +-b``: the element size is ``2a/nx x 2b/ny``.
    """
    nx, ny = (elements, elements) if np.isscalar(elements) else elements
    dx, dy = 2.0 * a / nx, 2.0 * b / ny
    return SurfaceGrid(int(nx) + 2 * margin, int(ny) + 2 * margin, dx, dy, -a - margin * dx, -b - margin * dy)


def hertz_pressure(grid: SurfaceGrid, a: float, b: float, normal_load: float) -> np.ndarray:
    """Hertz's ``p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` at the element centres [Pa], scaled so that ``sum p dA = Fn``.

    Johnson, Contact Mechanics, eq 4.39 (the ellipsoidal pressure); the scale puts load balance at round-off on
    the grid (it differs from ``3 Fn / (2 pi a b)`` by the quadrature error of the sampled ellipsoid).
    """
    x, y = grid.mesh()
    shape = np.sqrt(np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None))
    total = shape.sum() * grid.area
    if not total > 0.0:
        raise ValueError(f"the grid ({grid.nx} x {grid.ny} elements of {grid.dx:.3g} x {grid.dy:.3g} m) has no "
                         f"element centre inside the ellipse a = {a:.3g} m, b = {b:.3g} m")
    return shape * (normal_load / total)


@dataclass(frozen=True)
class NormalSolution3D:
    """The discretised normal problem's pressure [Pa], contact mask, approach delta [m] and status."""

    pressure: np.ndarray
    contact: np.ndarray
    approach: float
    iterations: int
    converged: bool
    message: str
    load_balance: float


def solve_normal(operator: SurfaceOperator, gap: np.ndarray, normal_load: float, shear_modulus: float,
                 tolerance: float = 1e-10, max_iterations: int = NORMAL_ITERATIONS,
                 initial: np.ndarray | None = None) -> NormalSolution3D:
    """Normal contact on the grid by Polonsky & Keer's constrained conjugate gradients (Wear 231, 1999).

    Solves ``g = h0 + A_zz p / G - delta >= 0``, ``p >= 0``, ``p g = 0``, ``dA sum p = Fn`` (Kalker 1990,
    sec. 5.3; the approach delta is the mean of ``h0 + u_z`` over the contact); stops when the pressure changes
    by less than ``tolerance`` relative to the load in one iteration.

    Parameters
    ----------
    operator : SurfaceOperator
        Influence coefficients of the grid (G = 1 Pa).
    gap : ndarray
        Undeformed gap h0 [m] at the element centres, e.g. ``A x^2 + B y^2``.
    normal_load : float
        Fn [N] > 0.
    shear_modulus : float
        G [Pa].
    initial : ndarray, optional
        A pressure [Pa] on the grid to start from (a nearby case's solution), its negative part dropped and scaled
        to the load (ValueError for another shape); None, or one without a positive finite sum: the load spread
        over the whole grid.
    """
    grid = operator.grid
    area = grid.area
    p = None if initial is None else np.maximum(np.asarray(initial, dtype=float), 0.0)
    if p is not None and p.shape != gap.shape:
        raise ValueError(f"the initial pressure has the shape {p.shape}, the grid {gap.shape}")
    total = 0.0 if p is None else float(p.sum())
    if p is not None and math.isfinite(total) and total > 0.0:
        p *= normal_load / (total * area)
    else:
        p = np.full(gap.shape, normal_load / (area * gap.size))
    direction = np.zeros(gap.shape)
    previous = 1.0
    restart = True
    change = math.inf
    approach = 0.0
    for iteration in range(1, max_iterations + 1):
        contact = p > 0.0
        surface = gap + operator.normal(p) / shear_modulus
        approach = float(surface[contact].mean())
        residual = np.where(contact, surface - approach, 0.0)
        norm = float(np.sum(residual * residual))
        direction = residual + (0.0 if restart else norm / previous) * direction
        direction[~contact] = 0.0
        previous = norm
        response = operator.normal(direction) / shear_modulus
        response -= response[contact].mean()
        denominator = float(np.sum(response[contact] * direction[contact]))
        step = norm / denominator if denominator > 0.0 else 0.0
        old = p
        p = np.clip(p - step * direction, 0.0, None)
        overlap = (p == 0.0) & (surface - approach < 0.0)
        restart = bool(overlap.any())
        if restart:
            p[overlap] -= step * (surface[overlap] - approach)
        p *= normal_load / (p.sum() * area)
        change = float(np.abs(p - old).sum() * area / normal_load)
        if change <= tolerance:
            balance = abs(p.sum() * area - normal_load) / normal_load
            return NormalSolution3D(p, p > 0.0, approach, iteration, True, "converged", balance)
    balance = abs(p.sum() * area - normal_load) / normal_load
    return NormalSolution3D(p, p > 0.0, approach, max_iterations, False,
                            f"pressure still changes by {change:.2e} of the load after {max_iterations} iterations",
                            balance)


@dataclass(frozen=True)
class SteadySolution3D:
    """Steady tangential solution on the grid.

    Attributes
    ----------
    traction_x, traction_y : ndarray
        q [Pa] the wheel exerts on the rail.
    slip_x, slip_y : ndarray
        s [1] (relative slip velocity of the wheel over V).
    stick : ndarray
        Elements in stick (``|q + r s| <= g``).
    bound : ndarray
        g = mu p [Pa] at the solution's slip velocities.
    newton_iterations : int
        Newton steps taken.
    applications : int
        FFT operator applications spent (the rolling operator in residuals and GMRES products, the preconditioner):
        the solve's work, which ``max_applications`` bounds.
    converged : bool
    message : str
    residual : float
        ``max |q - P_g(q + r s)| / max g`` [1] of the returned traction.
    """

    traction_x: np.ndarray
    traction_y: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray
    stick: np.ndarray
    bound: np.ndarray
    newton_iterations: int
    applications: int
    converged: bool
    message: str
    residual: float


class _Problem:
    """The steady stick/slip problem on one grid: operator, pressure, rigid slip, friction; the fixed-point map
    ``F(q) = q - P_g(q + r s(q))`` and its semismooth Jacobian."""

    def __init__(self, operator, pressure, rigid_slip, shear_modulus, friction, rolling_speed):
        self.op = operator
        self.contact = pressure > 0.0
        self.index = np.flatnonzero(self.contact.ravel())
        self.m = self.index.size
        self.p = pressure
        self.wx, self.wy = (np.where(self.contact, w, 0.0) for w in rigid_slip)
        self.G = shear_modulus
        self.friction = friction
        self.speed = rolling_speed
        diag = 0.5 * (operator.diagonal["rxx"] + operator.diagonal["ryy"])
        self.r = shear_modulus / diag  # the projection's scale: the slip of one element's own traction
        grid = operator.grid
        self.dx = grid.dx
        spectra = operator.spectra
        self.sxx, self.syy, self.sxy = spectra["xx"], spectra["yy"], spectra["xy"]
        self.det = self.sxx * self.syy - self.sxy * self.sxy
        self.applications = 0
        """FFT operator applications so far (:attr:`SteadySolution3D.applications`)."""

    def pack(self, x, y):
        return np.concatenate((x.ravel()[self.index], y.ravel()[self.index]))

    def unpack(self, v):
        x = np.zeros(self.p.size)
        y = np.zeros(self.p.size)
        x[self.index] = v[:self.m]
        y[self.index] = v[self.m:]
        return x.reshape(self.p.shape), y.reshape(self.p.shape)

    def slip(self, qx, qy):
        self.applications += 1
        kx, ky = self.op.rolling(qx, qy)
        return (np.where(self.contact, self.wx - kx / self.G, 0.0),
                np.where(self.contact, self.wy - ky / self.G, 0.0))

    def bound(self, sx, sy):
        if self.friction.is_constant:
            return self.friction.static_coefficient * self.p
        return self.friction.coefficient(self.speed * np.hypot(sx, sy)) * self.p

    def state(self, qx, qy):
        """Residual F and what the Jacobian needs at q."""
        sx, sy = self.slip(qx, qy)
        g = self.bound(sx, sy)
        zx, zy = qx + self.r * sx, qy + self.r * sy
        zn = np.hypot(zx, zy)
        stick = self.contact & (zn <= g)
        safe = np.where(zn > 0.0, zn, 1.0)
        factor = np.where(stick, 1.0, g / safe)
        fx = np.where(self.contact, qx - zx * factor, 0.0)
        fy = np.where(self.contact, qy - zy * factor, 0.0)
        return {"sx": sx, "sy": sy, "g": g, "zx": zx, "zy": zy, "zn": safe, "stick": stick, "factor": factor,
                "fx": fx, "fy": fy}

    def jacobian(self, st):
        """The semismooth Jacobian at a state as a LinearOperator on the packed contact unknowns."""
        stick, factor = st["stick"], st["factor"]
        nx, ny = st["zx"] / st["zn"], st["zy"] / st["zn"]
        if self.friction.is_constant:
            slope = None
        else:
            sn = np.hypot(st["sx"], st["sy"])
            slope = self.friction.derivative(self.speed * sn) * self.speed * self.p
            ux = np.where(sn > 0.0, st["sx"] / np.where(sn > 0.0, sn, 1.0), nx)
            uy = np.where(sn > 0.0, st["sy"] / np.where(sn > 0.0, sn, 1.0), ny)
        def apply(v):
            self.applications += 1
            vx, vy = self.unpack(v)
            kx, ky = self.op.rolling(vx, vy)
            dsx, dsy = -kx / self.G, -ky / self.G
            tx, ty = vx + self.r * dsx, vy + self.r * dsy
            dot = nx * tx + ny * ty
            px, py = factor * (tx - nx * dot), factor * (ty - ny * dot)
            if slope is not None:
                ds = slope * (ux * dsx + uy * dsy)
                px, py = px + nx * ds, py + ny * ds
            ox = np.where(stick, -self.r * dsx, vx - px)
            oy = np.where(stick, -self.r * dsy, vy - py)
            return self.pack(ox, oy)

        return LinearOperator((2 * self.m, 2 * self.m), matvec=apply, dtype=float)

    def full_stick(self):
        """``P_g`` of the full-stick traction ``K q = G w`` on the contact: the start of Newton (stick at the leading
        edge, the traction bound reached behind it, as in Carter's and Kalker's solutions)."""
        stick = self.contact

        def apply(v):
            self.applications += 1
            kx, ky = self.op.rolling(*self.unpack(v))
            return self.pack(kx * (self.r / self.G), ky * (self.r / self.G))

        operator = LinearOperator((2 * self.m, 2 * self.m), matvec=apply, dtype=float)
        rhs = self.pack(self.r * self.wx, self.r * self.wy)
        solution, _ = gmres(operator, rhs, rtol=1e-3, atol=0.0, restart=GMRES_RESTART, maxiter=1,
                            M=self.preconditioner(stick))
        qx, qy = self.unpack(solution)
        g = self.bound(0.0 * qx, 0.0 * qy)
        size = np.hypot(qx, qy)
        factor = np.where(size > g, g / np.where(size > 0.0, size, 1.0), 1.0)
        return qx * factor, qy * factor

    def preconditioner(self, stick):
        """Left preconditioner: on stick elements the causal inverse of ``r K / G``, identity on slip ones."""
        shape = self.op.shape
        nx, ny = self.op.grid.nx, self.op.grid.ny

        def apply(v):
            self.applications += 1
            vx, vy = self.unpack(v)
            # K q = D A q: D^-1 sums the slip rate from the leading edge (x = +a, the last row) upstream
            ux = np.where(stick, vx, 0.0)[::-1].cumsum(axis=0)[::-1] * (self.dx * self.G / self.r)
            uy = np.where(stick, vy, 0.0)[::-1].cumsum(axis=0)[::-1] * (self.dx * self.G / self.r)
            fx, fy = sfft.rfft2(ux, s=shape), sfft.rfft2(uy, s=shape)
            qx = sfft.irfft2((self.syy * fx - self.sxy * fy) / self.det, s=shape)[:nx, :ny]
            qy = sfft.irfft2((self.sxx * fy - self.sxy * fx) / self.det, s=shape)[:nx, :ny]
            return self.pack(np.where(stick, qx, vx), np.where(stick, qy, vy))

        return LinearOperator((2 * self.m, 2 * self.m), matvec=apply, dtype=float)


def solve_steady(operator: SurfaceOperator, pressure: np.ndarray, rigid_slip: tuple[np.ndarray, np.ndarray],
                 shear_modulus: float, friction: FrictionLaw, rolling_speed: float = 1.0, tolerance: float = 1e-8,
                 max_iterations: int = NEWTON_ITERATIONS, initial: tuple[np.ndarray, np.ndarray] | None = None,
                 max_applications: int | None = None) -> SteadySolution3D:
    """Steady rolling stick/slip by semismooth Newton on ``F(q) = q - P_g(q + r s(q)) = 0`` (module docstring).

    Parameters
    ----------
    operator : SurfaceOperator
        Influence coefficients (G = 1 Pa) of the grid.
    pressure : ndarray
        p [Pa] on the grid; the contact is ``p > 0``.
    rigid_slip : (ndarray, ndarray)
        ``(w_x, w_y)`` [1] at the element centres.
    shear_modulus : float
        G [Pa].
    friction : FrictionLaw
        ``mu(v)`` of the slip velocity ``v = V |s|`` [m/s].
    rolling_speed : float
        V [m/s].
    tolerance : float
        On ``max |F| / max g``.
    max_iterations : int
        Newton cap; beyond it the result says so (``converged`` False and the residual in the message).
    initial : (ndarray, ndarray), optional
        Starting traction (a neighbouring case's solution).
    max_applications : int, optional
        Work cap: FFT operator applications the solve may spend (:attr:`SteadySolution3D.applications`).  No Newton
        step starts, and no GMRES iteration, beyond it; a solve stopped by it returns ``converged`` False and says
        so.  None: only ``max_iterations`` and the stall bound the work.
    """
    problem = _Problem(operator, pressure, rigid_slip, shear_modulus, friction, rolling_speed)
    if problem.m == 0:
        zero = np.zeros(pressure.shape)
        return SteadySolution3D(zero, zero, zero, zero, np.zeros(pressure.shape, bool), zero, 0, 0, False,
                                "no element in contact", math.nan)
    if initial is None:
        qx, qy = problem.full_stick()
    else:
        qx, qy = (np.where(problem.contact, q, 0.0) for q in initial)
    cap = math.inf if max_applications is None else max_applications
    run = _newton(problem, qx, qy, tolerance, max_iterations, cap)
    st = run.state
    message = run.message
    if not run.converged and not friction.is_constant:
        sn = np.hypot(st["sx"], st["sy"])
        falling = float(np.max(-friction.derivative(rolling_speed * sn) * rolling_speed * pressure / problem.r))
        if falling > 1.0:
            message += (f"; the friction law falls faster than the grid resolves: an element's slip equation is not "
                        f"monotone where -(p / r) V dmu/dv = {falling:.3g} > 1 (r = G / K_ii), so the discrete "
                        f"steady problem may have several solutions")
    return SteadySolution3D(run.qx, run.qy, st["sx"], st["sy"], st["stick"], st["g"], run.iterations,
                            problem.applications, run.converged, message, run.residual)


STALL_WINDOW = 10
"""Newton stops when ``|F|_2`` has not halved over this many iterations (a stagnating iteration)."""


class _Run(NamedTuple):
    qx: np.ndarray
    qy: np.ndarray
    state: dict
    iterations: int
    converged: bool
    message: str
    residual: float


def _newton(problem: _Problem, qx, qy, tolerance: float, max_iterations: int, cap: float) -> _Run:
    """Semismooth Newton from ``(qx, qy)``: GMRES per step, backtracking on ``|F|_2``, stops at the tolerance,
    the cap of iterations or of operator applications, a stall (:data:`STALL_WINDOW`) or a residual that is not a
    finite number (a rigid slip beyond floating point)."""
    st = problem.state(qx, qy)
    scale = float(st["g"].max()) if st["g"].max() > 0.0 else 1.0
    norm = float(np.hypot(st["fx"], st["fy"]).max()) / scale
    merit = float(np.sum(st["fx"] ** 2 + st["fy"] ** 2))
    history = [merit]
    for iteration in range(max_iterations + 1):
        if norm <= tolerance:
            return _Run(qx, qy, st, iteration, True, "converged", norm)
        if not math.isfinite(norm):  # NaN never stalls nor converges: stop at once
            return _Run(qx, qy, st, iteration, False,
                        f"the residual is {norm!r} after {iteration} Newton iterations: the rigid slip or the "
                        "tractions lie beyond floating point", norm)
        if iteration == max_iterations:
            break
        if len(history) > STALL_WINDOW and history[-1] > 0.5 * history[-1 - STALL_WINDOW]:
            return _Run(qx, qy, st, iteration, False,
                        f"Newton stagnates after {iteration} iterations: residual {norm:.2e} of max mu p "
                        f"(tolerance {tolerance:.1e})", norm)
        # a GMRES iteration applies the operator and the preconditioner; the step's backtracking up to 7 residuals
        left = (cap - problem.applications - 7) // 2
        if left < 1:
            return _Run(qx, qy, st, iteration, False,
                        f"the work cap of {cap:.0f} operator applications is reached after {iteration} Newton "
                        f"iterations: residual {norm:.2e} of max mu p (tolerance {tolerance:.1e})", norm)
        jac = problem.jacobian(st)
        rhs = -problem.pack(st["fx"], st["fy"])
        # inexact Newton: the linear solve only as tight as needed, and in the last steps no tighter than the
        # tolerance asks (the step's linear error is about forcing times the residual)
        forcing = min(0.1, max(0.1 * tolerance, norm, 0.5 * tolerance / norm))
        restart = int(min(GMRES_RESTART, left))
        step, _ = gmres(jac, rhs, rtol=forcing, atol=0.0, restart=restart,
                        maxiter=int(max(1, min(GMRES_CYCLES, left // restart))),
                        M=problem.preconditioner(st["stick"]))
        dx, dy = problem.unpack(step)
        # backtracking on the merit |F|_2: a full step first; one that does not decrease it is halved, at most 6 times
        t = 1.0
        for _ in range(7):
            trial = problem.state(qx + t * dx, qy + t * dy)
            trial_merit = float(np.sum(trial["fx"] ** 2 + trial["fy"] ** 2))
            if trial_merit < (1.0 - 1e-4 * t) * merit:
                break
            t *= 0.5
        qx, qy, st, merit = qx + t * dx, qy + t * dy, trial, trial_merit
        norm = float(np.hypot(st["fx"], st["fy"]).max()) / scale
        history.append(merit)
    return _Run(qx, qy, st, max_iterations, False,
                f"Newton did not converge in {max_iterations} iterations: residual {norm:.2e} of max mu p "
                f"(tolerance {tolerance:.1e})", norm)


def total_forces(grid: SurfaceGrid, qx: np.ndarray, qy: np.ndarray) -> tuple[float, float, float]:
    """``(Fx, Fy, Mz)`` [N, N, N m]: ``sum q dA`` and ``sum (x q_y - y q_x) dA`` about the contact centre."""
    x, y = grid.mesh()
    area = grid.area
    return (float(qx.sum() * area), float(qy.sum() * area), float((x * qy - y * qx).sum() * area))
