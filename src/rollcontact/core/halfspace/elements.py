"""Private core of the discretised solver: grid, exact influence coefficients and the two active-set solvers.

Suffixes: ``_m`` metres, ``_pa`` pascals where a name would otherwise be ambiguous.  All matrices act on
piecewise-constant element values on a uniform grid of ``n`` elements of width ``h``; element ``j`` covers
``[x_j - h/2, x_j + h/2]`` and every equation is collocated at the element centres ``x_i``.

Influence coefficients (Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, 1990, ch. 5, for the 2D
half-plane; docs/physics.md, Conventions):

* displacement, log kernel: with ``F(y) = y ln|y| - y``,
  ``int_{z_j - h/2}^{z_j + h/2} ln(|x_i - z| / L) dz = h [F(k + 1/2) - F(k - 1/2) + ln(h / L)]``,
  ``k = (x_i - x_j) / h`` (any real shift, not only integers);
* gradient, Cauchy kernel: ``PV-int_{elem j} dz / (x_i - z) = ln|(k + 1/2) / (k - 1/2)|``, and its average
  over the upwind interval ``[x_{i-1}, x_i]`` equals the difference of the log coefficients of ``i`` and ``i-1``
  divided by ``h``.  That averaged form is the steady operator used here, the exact ``ds = h`` limit of the
  transient marching (the centred collocation is antisymmetric with zero diagonal and singular for an odd
  number of stick elements).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg
from scipy.linalg import lapack

MIN_ELEMENTS = 8


MAX_ELEMENTS = 4000  # dense n x n matrices: 4000^2 doubles are 128 MB each


@dataclass(frozen=True)
class Grid:
    """Uniform grid of ``elements`` piecewise-constant elements on ``[x_min, x_max]`` [m], x from the axis.

    Parameters
    ----------
    x_min, x_max : float
        Window [m] in the axis-fixed coordinate ``x = X - x_c``; material flows in +x.
    elements : int
        Number of elements n, ``MIN_ELEMENTS <= n <= MAX_ELEMENTS``.
    """

    x_min: float
    x_max: float
    elements: int

    def __post_init__(self):
        if isinstance(self.elements, bool) or not isinstance(self.elements, (int, np.integer)):
            raise ValueError(f"elements must be an integer, got {self.elements!r}")
        if not MIN_ELEMENTS <= self.elements <= MAX_ELEMENTS:
            raise ValueError(f"elements = {self.elements} is out of range: it must lie in "
                             f"[{MIN_ELEMENTS}, {MAX_ELEMENTS}]")
        for name in ("x_min", "x_max"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"window {name} must be finite, got {getattr(self, name)!r}")
        if not self.x_max > self.x_min:
            raise ValueError(f"window = ({self.x_min!r}, {self.x_max!r}) m is empty: x_max must exceed x_min")
        object.__setattr__(self, "elements", int(self.elements))

    @property
    def length(self) -> float:
        """Window length [m]."""
        return self.x_max - self.x_min

    @property
    def element_width(self) -> float:
        """h [m]."""
        return self.length / self.elements

    @property
    def centres(self) -> np.ndarray:
        """Element centres x_i [m]."""
        return self.x_min + (np.arange(self.elements) + 0.5) * self.element_width


def log_coefficients(k):
    """``int_{-1/2}^{1/2} ln|k - t| dt = F(k + 1/2) - F(k - 1/2)``, ``F(y) = y ln|y| - y``, for offsets k [1]."""
    k = np.asarray(k, dtype=float)

    def antiderivative(y):
        ay = np.abs(y)
        return np.where(ay > 0.0, y * np.log(np.where(ay > 0.0, ay, 1.0)), 0.0) - y

    return antiderivative(k + 0.5) - antiderivative(k - 0.5)


class FactorCache:
    """Factorisations of principal submatrices ``A[S, S]``, keyed by the index set S, with ``A[S,S]^-1 1``.

    Stick sets repeat from step to step once a transient settles, so each factorisation is reused; the cache
    keeps the ``size`` most recent ones.
    """

    def __init__(self, matrix: np.ndarray, symmetric: bool, size: int = 16):
        self.matrix = matrix
        self.symmetric = symmetric
        self.size = size
        self.store: dict[bytes, tuple] = {}

    def get(self, mask: np.ndarray):
        """Return ``(solve, z, idx)`` for the set ``mask``: ``solve(r) = A[S,S]^-1 r``, ``z = A[S,S]^-1 1``."""
        key = mask.tobytes()
        hit = self.store.get(key)
        if hit is not None:
            return hit
        idx = np.flatnonzero(mask)
        sub = self.matrix[np.ix_(idx, idx)]
        # the LAPACK solves directly: scipy's cho_solve/lu_solve wrappers cost several times the solve itself per
        # call on the small stick sets of a transient substep (same routines, same results)
        if self.symmetric:
            factor, lower = linalg.cho_factor(sub, check_finite=False)

            def solve(r, factor=factor, lower=lower):
                return lapack.dpotrs(factor, r, lower=lower)[0]
        else:
            lu, pivots = linalg.lu_factor(sub, check_finite=False)

            def solve(r, lu=lu, pivots=pivots):
                return lapack.dgetrs(lu, pivots, r)[0]
        entry = (solve, solve(np.ones(idx.size)), idx)
        if len(self.store) >= self.size:
            self.store.pop(next(iter(self.store)))
        self.store[key] = entry
        return entry


class Operators:
    """Influence matrices of one grid and one contact modulus, with cached factorisations.

    Attributes
    ----------
    kappa : float
        2 / (pi E*) [1/Pa].
    working_datum : float
        L_w [m] = grid length: the log-kernel matrix ``M`` below is symmetric positive definite only for a datum
        above the logarithmic capacity of the window, a quarter of its length.
    M : ndarray
        ``M[i, j] = -kappa h [F(k+1/2) - F(k-1/2) + ln(h / L_w)]``: normal displacement (gap opening) at x_i per
        unit pressure on element j, and minus the tangential displacement for the datum L_w.
    K : ndarray
        Steady rolling operator ``K = (M - M_1) / h`` with ``M_1`` the log matrix shifted one element upwind:
        ``s = xi - K q`` is the steady slip (``du/dx = -K q``).
    """

    def __init__(self, grid: Grid, contact_modulus: float):
        self.grid = grid
        self.h = grid.element_width
        self.kappa = 2.0 / (math.pi * contact_modulus)
        self.working_datum = grid.length
        self.M = self.shifted(0.0)
        self.K = (self.M - self.shifted(1.0)) / self.h
        # shared between solvers through operators_for(): nobody may change them in place
        self.M.flags.writeable = False
        self.K.flags.writeable = False
        self.m_factors = FactorCache(self.M, symmetric=True)
        self.k_factors = FactorCache(self.K, symmetric=False)
        self.shift_cache: dict[float, np.ndarray] = {}

    def shifted(self, shift: float) -> np.ndarray:
        """``M`` evaluated at the upwind points ``x_i - shift h`` (Toeplitz, like M)."""
        n = self.grid.elements
        k = np.arange(n, dtype=float)
        scale = -self.kappa * self.h
        offset = math.log(self.h / self.working_datum)
        column = scale * (log_coefficients(k - shift) + offset)
        row = scale * (log_coefficients(-k - shift) + offset)
        return linalg.toeplitz(column, row)

    def convected(self, distance: float) -> np.ndarray:
        """``M`` at ``x_i - distance``: the old displacement field seen by the particles now at x_i."""
        shift = distance / self.h
        key = round(shift, 12)
        # least recently used out: a transient's whole-element shift is used every step, its provisional
        # fractional shifts (InstationaryModel.advance) change with the phase of the roll
        matrix = self.shift_cache.pop(key, None)
        if matrix is None:
            if len(self.shift_cache) >= 8:
                self.shift_cache.pop(next(iter(self.shift_cache)))
            matrix = self.M if shift == 0.0 else self.shifted(shift)
        self.shift_cache[key] = matrix
        return matrix


@functools.lru_cache(maxsize=8)
def operators_for(grid: Grid, contact_modulus: float) -> Operators:
    """Cached :class:`Operators`: creep curves and time loops on one grid build the matrices once."""
    return Operators(grid, contact_modulus)


@dataclass(frozen=True)
class NormalSolution:
    """Solution of the discretised normal problem on a grid.

    Attributes
    ----------
    pressure : ndarray
        p_i [Pa] on the elements.
    gap : ndarray
        Deformed gap g_i [m] at the element centres (0 in contact).
    approach : float
        Rigid approach c [m] for the working datum (only differences are physical).
    contact : ndarray
        Boolean mask of elements in contact.
    iterations : int
        Active-set iterations.
    converged : bool
        True when the active set settled and the certificate holds.
    message : str
        Status.
    certificate : dict
        ``load_balance`` |h sum p - N'| / N', ``penetration`` max(-g)/(kappa N') outside contact,
        ``gap_in_contact`` max|g|/(kappa N') in contact, ``negative_pressure`` max(-p)/max p,
        ``complementarity`` max|p g| / (max p kappa N').
    """

    pressure: np.ndarray
    gap: np.ndarray
    approach: float
    contact: np.ndarray
    iterations: int
    converged: bool
    message: str
    certificate: dict

    @property
    def residual(self) -> float:
        """Largest certificate entry (dimensionless)."""
        return max(self.certificate.values()) if self.certificate else 0.0


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Contiguous runs ``[start, stop)`` of True in a boolean mask (contact patches, stick zones)."""
    padded = np.concatenate(([False], mask, [False])).astype(np.int8)
    edges = np.flatnonzero(np.diff(padded))
    return list(zip(edges[0::2].tolist(), edges[1::2].tolist(), strict=True))


DEFLECTION_RANGE = (1e-290, 1e290)
"""Range [m] of the deflection scale ``kappa N'`` that :func:`solve_normal` resolves: the gaps it certifies
(metres at most) over that scale, and that scale over them, stay within floating point (a load per length of
1e-280 N/m or 1e300 N/m is outside it, far outside any contact)."""


def solve_normal(ops: Operators, gap0: np.ndarray, load: float, tolerance: float,
                 max_iterations: int) -> NormalSolution:
    """Normal contact by Kalker's NORM active set with the load constraint (unknown rigid approach).

    Solves ``g = h0 + M p - c``, ``g >= 0``, ``p >= 0``, ``p g = 0``, ``h sum p = N'`` (Kalker 1990, sec. 5.3;
    paper eqs 1-4 in gap form): on the current contact set I, ``M_II p_I = c - h0_I`` with c from the load;
    negative pressures leave I, penetrating elements join it.  ``M`` is SPD (working datum), so each set costs
    one Cholesky factorisation; the load constraint is eliminated with ``z = M_II^-1 1``.

    Parameters
    ----------
    ops : Operators
        Influence matrices of the grid.
    gap0 : ndarray
        Undeformed gap h0 [m] at the element centres.
    load : float
        N' [N/m] > 0.
    tolerance : float
        Relative tolerance on gaps (scale kappa N') and pressures.
    max_iterations : int
        Active-set iteration cap.
    """
    n = gap0.size
    h = ops.h
    gap_scale = ops.kappa * load
    if not DEFLECTION_RANGE[0] <= gap_scale <= DEFLECTION_RANGE[1]:
        raise ValueError(f"normal_load_per_length = {load!r} N/m is beyond what the discretised solver resolves: "
                         f"its deflection scale kappa N' = {gap_scale:.3g} m lies outside [{DEFLECTION_RANGE[0]:g}, "
                         f"{DEFLECTION_RANGE[1]:g}] m")
    # start from the elements the rigid profile would penetrate at the Hertz depth: usually one step away
    contact = gap0 <= gap0.min() + gap_scale
    seen = set()
    p = np.zeros(n)
    c = 0.0
    message = "active set did not settle within max_iterations"
    iterations = 0
    settled = False
    for iteration in range(1, max_iterations + 1):
        iterations = iteration
        key = contact.tobytes()
        if key in seen:
            message = "active set cycles"
            break
        seen.add(key)
        solve, z, idx = ops.m_factors.get(contact)
        # the rigid gap's level over the set goes into the approach, not through M^-1: on a steep surface it is
        # many orders above the deflections, and p = M^-1 (c - h0) would lose them to cancellation
        level = gap0[idx].min()
        y = solve(level - gap0[idx])
        shift = (load / h - y.sum()) / z.sum()
        c = level + shift
        p_i = y + shift * z
        p = np.zeros(n)
        p[idx] = p_i
        negative = p_i < -tolerance * max(p_i.max(), 0.0)
        if negative.any():
            contact[idx[negative]] = False
            if not contact.any():
                message = "no element carries pressure"
                break
            continue
        gap = gap0 + ops.M @ p - c
        penetrating = ~contact & (gap < -tolerance * gap_scale)
        if penetrating.any():
            contact |= penetrating
            continue
        settled = True
        break
    pmax = p.max()
    negative_pressure = max(0.0, -p.min()) / pmax if pmax > 0 else 0.0
    p = np.clip(p, 0.0, None)
    gap = gap0 + ops.M @ p - c
    certificate = {
        "load_balance": abs(h * p.sum() - load) / load,
        "penetration": max(0.0, -gap[~contact].min()) / gap_scale if (~contact).any() else 0.0,
        "gap_in_contact": np.abs(gap[contact]).max() / gap_scale if contact.any() else 0.0,
        "negative_pressure": negative_pressure,
        "complementarity": float(np.abs((p / pmax) * (gap / gap_scale)).max()) if pmax > 0 else 0.0,
    }
    certified = settled and max(certificate.values()) <= 100.0 * tolerance
    if settled and not certified:
        message = f"certificate fails: {certificate}"
    elif settled:
        message = "converged"
    return NormalSolution(p, gap, float(c), contact.copy(), iterations, certified, message, certificate)


@dataclass(frozen=True)
class Control:
    """Linear side condition ``alpha c + beta h sum(q) = gamma`` on the stick-zone constant c.

    Creep control in steady rolling: ``(1, 0, xi)``; force control: ``(0, 1, T')``.  In a transient step c is
    the rigid shift corrected by the datum term: see :class:`rollcontact.line.halfspace.solver.TransientSolver`.
    """

    alpha: float
    beta: float
    gamma: float


@dataclass(frozen=True)
class StickSlipSolution:
    """Traction q [Pa], slip vector ``c + b - A q``, stick mask, constant c, iterations and status."""

    traction: np.ndarray
    slip: np.ndarray
    stick: np.ndarray
    constant: float
    iterations: int
    converged: bool
    message: str


def solve_stick_slip(matrix: np.ndarray, factors: FactorCache, b: np.ndarray, bound: np.ndarray,
                     contact: np.ndarray, control: Control, h: float, stick0: np.ndarray, sign0: np.ndarray,
                     slip_tolerance: float, max_iterations: int) -> StickSlipSolution:
    """Kalker's TANG active set for one step (or the steady state): stick/slip with Coulomb bounds.

    Unknowns q on the contact elements.  With ``slip = c + b - A q``: stick elements have ``slip = 0`` and
    ``|q| <= bound``; slip elements have ``q = bound sign`` and ``sign * slip >= 0`` (in slip q = mu p sign(s),
    docs/physics.md, Conventions).  Per set, ``A_SS q_S = b_S - A_SP q_P + c 1`` is solved with one (cached)
    factorisation and c follows from the side condition.  Violations swap sets (traction above the bound:
    stick -> slip with the traction's sign; slip against the traction: slip -> stick) until none remain.

    Parameters
    ----------
    matrix : ndarray
        A: ``M`` for a transient step, ``K`` for the steady state.
    factors : FactorCache
        Factorisations of A's principal submatrices.
    b : ndarray
        Known part of the slip (``M_ds q_old`` in a transient step, 0 in steady state).
    bound : ndarray
        mu p [Pa] per element.
    contact : ndarray
        Elements in contact (q = 0 elsewhere).
    control : Control
        Side condition fixing c.
    h : float
        Element width [m].
    stick0, sign0 : ndarray
        Initial stick mask and slip signs (warm start).
    slip_tolerance : float
        Absolute tolerance on the slip direction test (units of ``slip``).
    max_iterations : int
        Active-set iteration cap.
    """
    n = b.size
    stick = stick0 & contact
    sign = np.where(sign0 >= 0, 1.0, -1.0)
    seen = set()
    q = np.zeros(n)
    c = 0.0
    slip = np.zeros(n)
    message = "stick/slip set did not settle within max_iterations"
    for iteration in range(1, max_iterations + 1):
        slipping = contact & ~stick
        q = np.zeros(n)
        q[slipping] = bound[slipping] * sign[slipping]
        q_slip_sum = q.sum()
        if stick.any():
            solve, z, idx = factors.get(stick)
            y = solve(b[idx] - matrix[idx] @ q)
            denominator = control.alpha + control.beta * h * z.sum()
            if abs(denominator) <= 1e-12 * (abs(control.alpha) + abs(control.beta * h * z.sum())):
                return StickSlipSolution(q, slip, stick, c, iteration, False,
                                         "singular side condition (datum below the capacity of the stick zone)")
            c = (control.gamma - control.beta * h * (y.sum() + q_slip_sum)) / denominator
            q[idx] = y + c * z
        elif control.alpha != 0.0:
            c = (control.gamma - control.beta * h * q_slip_sum) / control.alpha
        else:
            return StickSlipSolution(q, slip, stick, c, iteration, False,
                                     "force control with every element slipping: force at the friction limit")
        slip = c + b - matrix @ q
        over = stick & (np.abs(q) > bound * (1.0 + 1e-12))
        wrong = slipping & (sign * slip < -slip_tolerance)
        if not over.any() and not wrong.any():
            return StickSlipSolution(q, slip, stick, float(c), iteration, True, "converged")
        key = stick.tobytes() + sign.tobytes()
        if key in seen:
            message = "stick/slip set cycles"
            break
        seen.add(key)
        sign[over] = np.sign(q[over])
        stick = (stick & ~over) | wrong
    return StickSlipSolution(q, slip, stick, float(c), max_iterations, False, message)


def initial_stick(contact: np.ndarray, fraction: float) -> np.ndarray:
    """Leading ``fraction`` of each contact patch (Carter's structure: stick at the leading edge)."""
    stick = np.zeros_like(contact)
    for start, stop in runs(contact):
        stick[start:start + int(math.ceil(fraction * (stop - start)))] = True
    return stick


def tangential_certificate(q, slip, stick, bound, contact, slip_scale) -> dict:
    """Certificate of a stick/slip solution (all entries dimensionless, 0 for an exact solution).

    ``stick_slip`` max|slip| in stick / slip_scale; ``traction_bound`` max(|q| - mu p) / max(mu p) over contact;
    ``slip_bound`` max| |q| - mu p | / max(mu p) in slip; ``slip_direction`` max(-sign(q) slip) / slip_scale in
    slip.
    """
    slipping = contact & ~stick
    qmax = bound.max() if bound.size and bound.max() > 0 else 1.0
    return {
        "stick_slip": float(np.abs(slip[stick]).max() / slip_scale) if stick.any() else 0.0,
        "traction_bound": float(max(0.0, (np.abs(q[contact]) - bound[contact]).max()) / qmax)
        if contact.any() else 0.0,
        "slip_bound": float(np.abs(np.abs(q[slipping]) - bound[slipping]).max() / qmax) if slipping.any() else 0.0,
        "slip_direction": float(max(0.0, (-np.sign(q[slipping]) * slip[slipping]).max()) / slip_scale)
        if slipping.any() else 0.0,
    }
