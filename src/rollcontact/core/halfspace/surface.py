"""The 3D elastic half-space on a rectangular grid: influence coefficients of rectangles and their FFT convolution.

Two identical elastic bodies (quasi-identity: the normal and the tangential problems decouple), shear modulus G
[Pa], Poisson ratio nu.  Tractions are piecewise constant on the ``nx x ny`` rectangular elements of a
:class:`SurfaceGrid` (``dx x dy`` each, x the rolling direction, y lateral) and every displacement is collocated
at the element centres.  Displacements are those of the two bodies together (their difference), per unit traction:

* normal, Boussinesq: ``u_z = (1 - nu) / (pi G) int int p / r``;
* tangential, Cerruti: ``u_x = 1/(pi G) int int [(1 - nu)/r + nu s^2/r^3] q_x + nu s t/r^3 q_y`` and
  ``u_y = 1/(pi G) int int nu s t/r^3 q_x + [(1 - nu)/r + nu t^2/r^3] q_y``,

with ``(s, t)`` the field point minus the source point and ``r = sqrt(s^2 + t^2)`` (Johnson, *Contact Mechanics*,
1985, eqs 3.22 and 3.86 at z = 0, doubled for the two bodies; Kalker, *Three-Dimensional Elastic Bodies in Rolling
Contact*, 1990, sec. 5.2).  Over a rectangle ``[s1, s2] x [t1, t2]`` each kernel integrates in closed form through
an antiderivative ``F`` with ``d^2 F / ds dt`` = kernel, evaluated at the four corners
(:func:`rectangle_integrals`, Love 1929 for the pressure):

* ``1/r``: ``F = s ln(t + r) + t ln(s + r)``;  ``s^2/r^3``: ``F = t ln(s + r)``;  ``t^2/r^3``: ``F = s ln(t + r)``;
* ``s t/r^3``: ``F = -r``.

The influence matrices are block-Toeplitz, so a displacement is a 2D convolution, done by FFT over the grid
zero-padded to at least ``2nx x 2ny`` (a size the FFT factors well) with the coefficients' transform computed
once per grid and nu (:func:`operator_for`, cached).  The steady rolling operator
(:meth:`SurfaceOperator.rolling`) is the upwind difference of the tangential displacement over one
element, with the material flowing in -x (leading edge at +x, Kalker's orientation): the coefficients at the
centres shifted one element upwind are exact, so the operator is itself a convolution.
"""

from __future__ import annotations

import copy
import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

MIN_ELEMENTS_3D = 4
MAX_ELEMENTS_3D = 1024  # per direction: the padded transforms of a 1024 x 1024 grid take 4 x 32 MB


@dataclass(frozen=True)
class SurfaceGrid:
    """Uniform grid of ``nx x ny`` rectangular elements ``dx x dy`` [m] starting at ``(x_min, y_min)`` [m].

    Element ``(i, j)`` covers ``[x_min + i dx, x_min + (i + 1) dx] x [y_min + j dy, y_min + (j + 1) dy]``; arrays
    on the grid have shape ``(nx, ny)``.
    """

    nx: int
    ny: int
    dx: float
    dy: float
    x_min: float
    y_min: float

    def __post_init__(self):
        for name in ("nx", "ny"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                raise ValueError(f"grid {name} must be an integer, got {value!r}")
            if not MIN_ELEMENTS_3D <= value <= MAX_ELEMENTS_3D:
                raise ValueError(f"grid {name} = {value} is out of range: it must lie in "
                                 f"[{MIN_ELEMENTS_3D}, {MAX_ELEMENTS_3D}]")
            object.__setattr__(self, name, int(value))
        for name in ("dx", "dy"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"grid element size {name} = {value!r} m must be finite and > 0")
        for name in ("x_min", "y_min"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"grid {name} = {getattr(self, name)!r} m must be finite")

    @classmethod
    def centred(cls, half_x: float, half_y: float, nx: int, ny: int) -> SurfaceGrid:
        """The grid of ``nx x ny`` elements covering ``[-half_x, half_x] x [-half_y, half_y]`` [m]."""
        return cls(nx, ny, 2.0 * half_x / nx, 2.0 * half_y / ny, -half_x, -half_y)

    @property
    def x(self) -> np.ndarray:
        """Element centres in x [m], shape (nx,)."""
        return self.x_min + (np.arange(self.nx) + 0.5) * self.dx

    @property
    def y(self) -> np.ndarray:
        """Element centres in y [m], shape (ny,)."""
        return self.y_min + (np.arange(self.ny) + 0.5) * self.dy

    @property
    def area(self) -> float:
        """Element area dx dy [m^2]."""
        return self.dx * self.dy

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Centre coordinates ``(X, Y)`` [m], each of shape (nx, ny)."""
        return np.meshgrid(self.x, self.y, indexing="ij")

    def carried(self, values: np.ndarray, source: SurfaceGrid) -> np.ndarray:
        """``values`` at the element centres of ``source`` carried to this grid's centres: bilinear between
        ``source``'s centres, 0 beyond its outer ones (a field that vanishes outside a contact: a pressure, a
        traction).  ``W_x values W_y^T`` with the 1D linear weights of each direction; on the same lattice the
        values themselves."""
        return _linear_weights(source.x, self.x) @ np.asarray(values, dtype=float) @ \
            _linear_weights(source.y, self.y).T


LATTICE_SLACK = 1e-9
"""Share of an element by which a point beyond the outer centres still takes the outer value (the rounding of the
centres of two grids on one lattice)."""


def _linear_weights(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``(target.size, source.size)`` weights of linear interpolation from the uniform points ``source`` to the
    points ``target``, rows of 0 beyond ``source``'s ends."""
    position = (target - source[0]) / (source[1] - source[0])
    weights = np.zeros((target.size, source.size))
    inside = (position >= -LATTICE_SLACK) & (position <= source.size - 1 + LATTICE_SLACK)
    at = np.clip(position[inside], 0.0, source.size - 1)
    low = np.minimum(np.floor(at).astype(int), source.size - 1)
    fraction = at - low
    rows = np.flatnonzero(inside)
    weights[rows, low] = 1.0 - fraction
    upper = low + 1 < source.size
    weights[rows[upper], low[upper] + 1] = fraction[upper]
    return weights


def _t_log_s_plus_r(s, t, r):
    """``t ln(s + r)``, without the cancellation of ``s + r`` for s < 0 (there ``s + r = t^2 / (r - s)``), and 0 at
    t = 0 (its limit)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        positive = t * np.log(np.where(s >= 0.0, s + r, 1.0))
        negative = t * (2.0 * np.log(np.abs(t)) - np.log(r - s))
        value = np.where(s >= 0.0, positive, negative)
    return np.where(t == 0.0, 0.0, value)


def rectangle_integrals(s1, s2, t1, t2) -> dict[str, np.ndarray]:
    """``int_{s1}^{s2} int_{t1}^{t2} k(s, t) dt ds`` [m] for the kernels ``1/r``, ``s^2/r^3``, ``t^2/r^3``,
    ``s t/r^3`` (keys ``"r"``, ``"ss"``, ``"tt"``, ``"st"``), from the corner antiderivatives in the module
    docstring.  Broadcasts; corners with ``r = 0`` (a field point on an element corner) are not allowed."""
    out = {key: 0.0 for key in ("r", "ss", "tt", "st")}
    for s, t, sign in ((s2, t2, 1.0), (s1, t2, -1.0), (s2, t1, -1.0), (s1, t1, 1.0)):
        s = np.asarray(s, dtype=float)
        t = np.asarray(t, dtype=float)
        r = np.hypot(s, t)
        t_ls = _t_log_s_plus_r(s, t, r)
        s_lt = _t_log_s_plus_r(t, s, r)
        out["r"] = out["r"] + sign * (s_lt + t_ls)
        out["ss"] = out["ss"] + sign * t_ls
        out["tt"] = out["tt"] + sign * s_lt
        out["st"] = out["st"] + sign * (-r)
    return out


def influence_coefficients(offset_x, offset_y, dx: float, dy: float, nu: float, shear_modulus: float = 1.0):
    """Displacements [m/Pa] at ``(offset_x, offset_y)`` [m] from the centre of a ``dx x dy`` element loaded by a
    unit uniform traction, both bodies together (module docstring).

    Returns
    -------
    dict
        ``"zz"`` normal displacement per unit pressure; ``"xx"``, ``"yy"``, ``"xy"`` tangential displacement
        component per unit traction component (``"xy"`` = u_x per q_y = u_y per q_x).
    """
    ox = np.asarray(offset_x, dtype=float)
    oy = np.asarray(offset_y, dtype=float)
    ints = rectangle_integrals(ox - dx / 2, ox + dx / 2, oy - dy / 2, oy + dy / 2)
    scale = 1.0 / (math.pi * shear_modulus)
    return {
        "zz": scale * (1.0 - nu) * ints["r"],
        "xx": scale * ((1.0 - nu) * ints["r"] + nu * ints["ss"]),
        "yy": scale * ((1.0 - nu) * ints["r"] + nu * ints["tt"]),
        "xy": scale * nu * ints["st"],
    }


def lattice_coefficients(low_x: int, count_x: int, low_y: int, count_y: int, dx: float, dy: float, nu: float,
                         shear_modulus: float = 1.0) -> dict[str, np.ndarray]:
    """:func:`influence_coefficients` at the offsets ``(i dx, j dy)`` of a block of elements, ``i = low_x .. low_x +
    count_x - 1`` and ``j = low_y .. low_y + count_y - 1`` (arrays ``(count_x, count_y)``): the corner
    antiderivatives (:func:`rectangle_integrals`) evaluated once on the lattice of the elements' corners, each
    element's integral the signed sum of its four corners' values, instead of four evaluations per element."""
    s = (low_x - 0.5 + np.arange(count_x + 1)) * dx
    t = (low_y - 0.5 + np.arange(count_y + 1)) * dy
    s, t = np.meshgrid(s, t, indexing="ij")
    r = np.hypot(s, t)
    t_ls = _t_log_s_plus_r(s, t, r)
    s_lt = _t_log_s_plus_r(t, s, r)
    ints = {}
    for key, corner in (("r", s_lt + t_ls), ("ss", t_ls), ("tt", s_lt), ("st", -r)):
        ints[key] = ((corner[1:, 1:] - corner[:-1, 1:]) - corner[1:, :-1]) + corner[:-1, :-1]
    scale = 1.0 / (math.pi * shear_modulus)
    return {
        "zz": scale * (1.0 - nu) * ints["r"],
        "xx": scale * ((1.0 - nu) * ints["r"] + nu * ints["ss"]),
        "yy": scale * ((1.0 - nu) * ints["r"] + nu * ints["tt"]),
        "xy": scale * nu * ints["st"],
    }


class SurfaceOperator:
    """FFT convolutions with the influence coefficients of one grid and one nu, for G = 1 Pa.

    The caller divides by its shear modulus.  Arrays in and out have the grid's shape ``(nx, ny)``.

    Attributes
    ----------
    grid : SurfaceGrid
    nu : float
        Poisson ratio, ``0 <= nu < 0.5`` or 0.5.
    spectra : dict
        rfft2 of the padded coefficients: ``"zz"``, ``"xx"``, ``"yy"``, ``"xy"`` (displacements) and ``"rxx"``,
        ``"ryy"``, ``"rxy"`` (the rolling operator, :meth:`rolling`).
    """

    def __init__(self, grid: SurfaceGrid, nu: float):
        self.grid = grid
        self.nu = nu
        nx, ny = grid.nx, grid.ny
        self.shape = (sfft.next_fast_len(2 * nx, real=True), sfft.next_fast_len(2 * ny, real=True))
        # offsets m = i - j of field minus source in units of the element; the padded index m mod L (L >= 2n) holds m
        # for -n < m <= n (the rolling operator needs m = n, the displacements only |m| < n)
        mx = np.arange(self.shape[0])
        mx = np.where(mx <= nx, mx, mx - self.shape[0])
        my = np.arange(self.shape[1])
        my = np.where(my <= ny, my, my - self.shape[1])
        # every offset and the rolling operator's upwind ones (the field point one element further in +x, m + 1) from
        # one table over the offsets they span
        low_x, low_y = int(mx.min()), int(my.min())
        table = lattice_coefficients(low_x, int(mx.max()) + 2 - low_x, low_y, int(my.max()) + 1 - low_y, grid.dx,
                                     grid.dy, nu)
        rows, columns = (mx - low_x)[:, None], (my - low_y)[None, :]
        here = {key: value[rows, columns] for key, value in table.items()}
        upwind = {key: value[rows + 1, columns] for key, value in table.items()}
        self.spectra = {key: sfft.rfft2(here[key]) for key in ("zz", "xx", "yy", "xy")}
        for key in ("xx", "yy", "xy"):
            self.spectra["r" + key] = sfft.rfft2((here[key] - upwind[key]) / grid.dx)
        self.diagonal = {key: float(here[key][0, 0]) for key in ("zz", "xx", "yy")}
        self.diagonal["rxx"] = float((here["xx"][0, 0] - upwind["xx"][0, 0]) / grid.dx)
        self.diagonal["ryy"] = float((here["yy"][0, 0] - upwind["yy"][0, 0]) / grid.dx)

    def _forward(self, values: np.ndarray) -> np.ndarray:
        return sfft.rfft2(values, s=self.shape)

    def _back(self, spectrum: np.ndarray) -> np.ndarray:
        return sfft.irfft2(spectrum, s=self.shape)[:self.grid.nx, :self.grid.ny]

    def normal(self, pressure: np.ndarray) -> np.ndarray:
        """Normal displacement ``u_z = A_zz p`` [m] (G = 1 Pa) of the pressure [Pa]."""
        return self._back(self.spectra["zz"] * self._forward(pressure))

    def tangential(self, qx: np.ndarray, qy: np.ndarray, prefix: str = "") -> tuple[np.ndarray, np.ndarray]:
        """Tangential displacements ``(u_x, u_y)`` [m] (G = 1 Pa) of the tractions [Pa]; with ``prefix="r"`` the
        rolling operator instead (:meth:`rolling`)."""
        fx = self._forward(qx)
        fy = self._forward(qy)
        sxy = self.spectra[prefix + "xy"]
        ux = self._back(self.spectra[prefix + "xx"] * fx + sxy * fy)
        uy = self._back(sxy * fx + self.spectra[prefix + "yy"] * fy)
        return ux, uy

    def rolling(self, qx: np.ndarray, qy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Steady rolling operator ``K q = (u(x) - u(x + dx)) / dx`` [1/m per Pa, G = 1 Pa], ``u = A q``.

        The material flows in -x, so ``x + dx`` is the centre one element upwind: the steady slip is
        ``s = w - K q / G`` (the displacement difference over the element the material has just crossed;
        Kalker 1990, sec. 5.4, backward difference as in CONTACT's steady state).
        """
        return self.tangential(qx, qy, prefix="r")


def operator_for(grid: SurfaceGrid, nu: float) -> SurfaceOperator:
    """Cached :class:`SurfaceOperator`: a creep curve on one grid transforms the coefficients once.  The coefficients
    depend on the grid's element counts and sizes and on nu, not on its origin: grids that differ only in where they
    lie share them (the operator returned carries the grid asked for), as the moving patches of a wheel do."""
    shared = _operator_for_shape(grid.nx, grid.ny, grid.dx, grid.dy, nu)
    if shared.grid == grid:
        return shared
    placed = copy.copy(shared)
    placed.grid = grid
    return placed


@functools.lru_cache(maxsize=16)
def _operator_for_shape(nx: int, ny: int, dx: float, dy: float, nu: float) -> SurfaceOperator:
    """The operator of the grid of this shape at the origin (cached: :func:`operator_for` places it)."""
    return SurfaceOperator(SurfaceGrid(nx, ny, dx, dy, 0.0, 0.0), nu)
