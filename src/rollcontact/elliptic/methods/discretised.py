"""Discretised 3D steady rolling (``"discretised"``): Kalker's exact theory on rectangular elements, the reference and
the fallback of the elliptic levels, as the 2D discretised method is for 2D.

The ellipse's ``2a x 2b`` is covered by ``nx x ny`` elements (``elements``, 60 x 60 by default); the pressure is
Hertz's sampled at the element centres and scaled to the load (``normal="hertz"``), or the discretised normal
problem on the gap ``A x^2 + B y^2`` (``normal="discretised"``, three elements of margin around the ellipse): on the
tangential forces the two differ by far less than the discretisation error (``tests/halfspace/test_rolling3d.py``).
The tangential problem is :func:`rollcontact.core.halfspace.rolling.solve_steady` (steady slip with the upwind rolling
operator, semismooth Newton with FFT-preconditioned GMRES, Coulomb or velocity-dependent friction), on the rigid
slip ``w = (xi - phi y, eta + phi x)``.  Forces are those the wheel exerts on the rail (docs/physics.md).

By default (``extrapolate=True``) it solves on ``elements`` and on half as many and returns the Richardson
extrapolation ``2 F(n) - F(n/2)``: the forces converge at first order, and on elements elongated along x (a/b > 1
at 60 x 60) a single grid misses the converged forces by more than 0.01 mu Fn where the pair does not, for about
an eighth more work (``benchmarks/bench_elliptic.py``, table A).
"""

from __future__ import annotations

import math

import numpy as np

from rollcontact.core.halfspace.rolling import (
    NEWTON_ITERATIONS,
    ellipse_grid,
    hertz_pressure,
    solve_normal,
    solve_steady,
    total_forces,
)
from rollcontact.core.halfspace.surface import MAX_ELEMENTS_3D, MIN_ELEMENTS_3D, operator_for
from rollcontact.core.method import AccuracyModel, MethodSpec
from rollcontact.elliptic.methods.common import no_load
from rollcontact.elliptic.result import EllipticResult, TractionField
from rollcontact.elliptic.scene import EllipticScene

DEFAULT_ELEMENTS = 60
"""Elements across 2a and across 2b."""


NORMAL_MARGIN = 3
"""Elements around the ellipse where the discretised normal problem may put contact."""


ERROR_PER_ELEMENT = 1.2
"""The error [1] of Fx, Fy (over mu Fn) and Mz (over mu Fn c) on one grid is at most this over the element count
across the shorter of nx, ny: a margin over the largest error times N in ``benchmarks/bench_elliptic.py``, section A
(the case matrix a/b 0.2..5, pure and combined creepages up to 3 saturation creepages, N = 60; the largest is spin
at a/b = 5, where the elements are five times longer than wide)."""


PAIR_ERROR = (20.0, 0.3)
"""The same for the Richardson pair ``2 F(N) - F(N/2)``: at most ``max(20 / N^2, 0.3 / N)``.  The pair's error falls
like 1/N^2 from N = 16 to 60 (``benchmarks/bench_elliptic.py``, section B, the pairs 8/16, 16/32 and 30/60: N^2 times
the largest error stays below 20); the first-order term, calibrated at N = 60 (section A, column 'pair'), keeps the
bound from trusting the second order beyond the grids measured."""


APPLICATION_SECONDS = (2.0e-4, 4.0e-4)
"""Modelled time [s] of one FFT operator application on a grid of ``nx x ny`` elements:
``APPLICATION_SECONDS[0] + APPLICATION_SECONDS[1] nx ny / 3600`` (the padded FFTs and the element-wise products grow
with the elements, the Python and scipy calls around them do not): ``benchmarks/calibrate_elliptic_levels.py``,
table D."""

WORK_CAP = (1500, 1.0)
"""Operator applications a solve on ``nx x ny`` elements may spend: ``WORK_CAP[0] (sqrt(nx ny) / 60)^WORK_CAP[1]``,
a margin over the largest the case matrix needs with Coulomb friction and the rail conditions' falling laws
(``benchmarks/calibrate_elliptic_levels.py``, table D); a solve the cap stops says so."""

SOLVE_SECONDS = 2e-3
"""Modelled time [s] of a solve's set-up on a grid (the pressure, the rigid slip, the start of Newton) beyond its
operator applications (``benchmarks/calibrate_elliptic_levels.py``, table D)."""


def work_cap(counts: tuple[int, int]) -> int:
    """Operator applications a solve on ``counts = (nx, ny)`` elements may spend (:data:`WORK_CAP`)."""
    return int(math.ceil(WORK_CAP[0] * (math.sqrt(counts[0] * counts[1]) / 60.0) ** WORK_CAP[1]))


def bounded_cost(counts: tuple[int, int]) -> float:
    """Modelled time [s] of a solve on ``counts`` elements that spends its whole :func:`work_cap`: an upper bound of
    the real time on the machine of the calibration."""
    nx, ny = counts
    return SOLVE_SECONDS + work_cap(counts) * (APPLICATION_SECONDS[0] + APPLICATION_SECONDS[1] * nx * ny / 3600.0)


LADDER = (16, 24, 32, 48, 60, 90, 120, 180, 240)
"""Element counts ``auto`` chooses from (alone, and as the finer level of a Richardson pair)."""


def element_counts(elements) -> tuple[int, int]:
    """``(nx, ny)`` from an int or a pair, each in ``[MIN_ELEMENTS_3D, MAX_ELEMENTS_3D]`` (ValueError naming the
    value otherwise)."""
    pair = (elements, elements) if np.isscalar(elements) else tuple(elements)
    if len(pair) != 2:
        raise ValueError(f"elements must be an int or a pair (nx, ny), got {elements!r}")
    for value in pair:
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise ValueError(f"elements must be integers, got {elements!r}")
        if not 2 * MIN_ELEMENTS_3D <= value <= MAX_ELEMENTS_3D - 2 * NORMAL_MARGIN:
            raise ValueError(f"elements = {value} is out of range: it must lie in "
                             f"[{2 * MIN_ELEMENTS_3D}, {MAX_ELEMENTS_3D - 2 * NORMAL_MARGIN}]")
    return int(pair[0]), int(pair[1])


def solve_on_grid(scene: EllipticScene, counts: tuple[int, int], normal: str, tolerance: float,
                  max_iterations: int, max_applications: int | None = None):
    """Grid, pressure, the steady solution and the forces (Fx, Fy, Mz) on ``counts`` elements."""
    h = scene.hertz
    nu, shear = scene.material.poisson_ratio, scene.shear_modulus
    if normal == "hertz":
        grid = ellipse_grid(h.a, h.b, counts)
        op = operator_for(grid, nu)
        pressure = hertz_pressure(grid, h.a, h.b, scene.normal_load)
        normal_message = None
    else:
        grid = ellipse_grid(h.a, h.b, counts, margin=NORMAL_MARGIN)
        op = operator_for(grid, nu)
        x, y = grid.mesh()
        gap = scene.longitudinal_curvature * x**2 + scene.lateral_curvature * y**2
        solution = solve_normal(op, gap, scene.normal_load, shear)
        pressure = solution.pressure
        normal_message = None if solution.converged else f"normal problem: {solution.message}"
    x, y = grid.mesh()
    xi, eta, phi = scene.creepages
    steady = solve_steady(op, pressure, (xi - phi * y, eta + phi * x), shear, scene.friction, scene.rolling_speed,
                          tolerance, max_iterations, max_applications=max_applications)
    return grid, pressure, steady, total_forces(grid, steady.traction_x, steady.traction_y), normal_message


def solve_discretised_3d(scene: EllipticScene, *, elements=DEFAULT_ELEMENTS, extrapolate: bool = True,
                         normal: str = "hertz", fields: bool = False, iteration_tolerance: float = 1e-8,
                         max_iterations: int = NEWTON_ITERATIONS, bounded: bool = True) -> EllipticResult:
    """Discretised steady rolling of an elliptic scene (module docstring).

    Parameters
    ----------
    scene : EllipticScene
    elements : int or (int, int)
        Elements across 2a and 2b.
    extrapolate : bool
        Richardson ``2 F(n) - F(n/2)`` from ``elements`` and half of them (both even); False: one grid.
    normal : {"hertz", "discretised"}
        Hertz's pressure sampled on the grid, or the discretised normal problem.
    fields : bool
        Attach the traction field (the finer grid's).
    iteration_tolerance : float
        Newton's tolerance on ``max |q - P_g(q + r s)| / max mu p``.
    max_iterations : int
        Newton cap; a solve that does not converge returns ``success`` False with the residual in the message.
    bounded : bool
        Cap each grid's work at :func:`work_cap` operator applications, so that no solve costs more than its
        modelled cost (:class:`DiscretisedAccuracy3D`); a solve the cap stops returns ``success`` False and says so.
        False: only ``max_iterations`` and the stall bound the work.

    Returns
    -------
    EllipticResult
        ``info``: ``elements``, ``newton_iterations``, ``operator_applications`` (FFT operator applications of both
        grids), ``residual``, ``stick_fraction``, ``error_estimate`` (:class:`DiscretisedAccuracy3D`).
    """
    counts = element_counts(elements)
    if normal not in ("hertz", "discretised"):
        raise ValueError(f"normal = {normal!r} is not one of 'hertz', 'discretised'")
    if extrapolate and (counts[0] % 2 or counts[1] % 2):
        raise ValueError(f"extrapolate needs even element counts, got {counts}")
    if scene.normal_load == 0.0:
        return no_load(scene, "discretised")
    grid, pressure, steady, forces, normal_message = solve_on_grid(
        scene, counts, normal, iteration_tolerance, max_iterations, work_cap(counts) if bounded else None)
    newton, applications = steady.newton_iterations, steady.applications
    success = steady.converged and normal_message is None
    messages = [m for m in (normal_message, None if steady.converged else steady.message) if m]
    options = {"elements": counts, "extrapolate": extrapolate}
    if extrapolate:
        half = (counts[0] // 2, counts[1] // 2)
        _, _, coarse, coarse_forces, coarse_normal = solve_on_grid(
            scene, half, normal, iteration_tolerance, max_iterations, work_cap(half) if bounded else None)
        forces = tuple(2.0 * f - g for f, g in zip(forces, coarse_forces, strict=True))
        newton += coarse.newton_iterations
        applications += coarse.applications
        success = success and coarse.converged and coarse_normal is None
        messages += [f"coarse level: {m}" for m in (coarse_normal, None if coarse.converged else coarse.message) if m]
    contact = pressure > 0.0
    info = {"elements": counts, "extrapolate": extrapolate, "normal": normal, "newton_iterations": newton,
            "operator_applications": applications, "residual": steady.residual,
            "stick_fraction": float(steady.stick[contact].mean()) if contact.any() else 0.0,
            "error_estimate": DiscretisedAccuracy3D().error(scene, options)}
    traction = None
    if fields:
        x, y = grid.mesh()
        traction = TractionField(x, y, pressure, steady.traction_x, steady.traction_y, steady.stick & contact)
    message = "converged" if success else "; ".join(messages)
    return EllipticResult.from_scene(scene, "discretised", success, message, forces, fields=traction, info=info)


solve_discretised_3d.options = ("elements", "extrapolate")


def inapplicable(scene: EllipticScene) -> str | None:
    """The discretised method treats every elliptic scene (any a/b, any friction law)."""
    return None


class DiscretisedAccuracy3D(AccuracyModel):
    """First-order error in the element count, ``ERROR_PER_ELEMENT / N`` with N = min(nx, ny) (the Richardson pair
    ``max(PAIR_ERROR[0] / N^2, PAIR_ERROR[1] / N)``), and the cost of each grid's capped work
    (:func:`bounded_cost`; the constants' docstrings cite the benchmark that calibrates them)."""

    floor = bounded_cost((LADDER[0], LADDER[0]))

    def ladder(self, scene):
        return (tuple({"elements": n, "extrapolate": False} for n in LADDER)
                + tuple({"elements": n, "extrapolate": True} for n in LADDER))

    @staticmethod
    def counts(options) -> tuple[int, int]:
        return element_counts(options.get("elements", DEFAULT_ELEMENTS))

    @staticmethod
    def paired(options) -> bool:
        return options.get("extrapolate", True)

    def cost(self, scene, options):
        nx, ny = self.counts(options)
        one = bounded_cost((nx, ny))
        return one + bounded_cost((nx // 2, ny // 2)) if self.paired(options) else one

    def error(self, scene, options):
        n = min(self.counts(options))
        if self.paired(options):
            return max(PAIR_ERROR[0] / n**2, PAIR_ERROR[1] / n)
        return ERROR_PER_ELEMENT / n


METHOD = MethodSpec("discretised", solve_discretised_3d, inapplicable, rank=100, fallback=True,
                    accuracy=DiscretisedAccuracy3D())
