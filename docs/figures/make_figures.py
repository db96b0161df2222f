"""Gallery: the figures 2-6 of J.B. Nielsen's paper on 2D rolling contact, reproduced with rollcontact, and figure 7,
the elliptic (3D) contact.

One command writes the six PNGs (default into this directory)::

    python docs/figures/make_figures.py [--quick] [--out DIR]

``--quick`` uses few points (the smoke tests of ``tests/test_gallery.py`` run it); the pictures keep their layout.
Each figure is a function ``figure_N(out, quick)`` that draws one PNG and returns a :class:`Rendered`: the path
and a dict of the key numbers shown, for the tests to check the physics.

Line styles follow the paper: rollcontact's solution solid, Carter's closed form dashed.  Every axis is in SI
units (mm and MPa where that reads better); the common case is a steel pair, N' = 1 MN/m, R = 0.46 m,
E = 210 GPa, nu = 0.28, mu = 0.3.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle
from scipy import optimize

import rollcontact as rc
from rollcontact.line.carter import CarterDistributions
from rollcontact.line.instationary import OscillatingForce, oscillating_force_chebyshev, quasi_steady_deviation
from rollcontact_cosim.cli import Progress

HERE = Path(__file__).resolve().parent

LOAD = 1e6
"""N' [N/m], normal load per unit length of every figure."""
RADIUS = 0.46
"""R [m], effective cylinder radius."""
MATERIAL = rc.Material(210e9, 0.28)
"""Steel on steel."""
MU = 0.3
"""Coulomb coefficient [1] (and the static coefficient of the falling law)."""
SPEED = 20.0
"""V [m/s], rolling speed of the velocity-dependent friction figures."""
FALLING = rc.ExponentialFalling(mu_static=MU, kinetic_ratio=0.4, decay=30.0)
"""The falling friction law of figures 4 and 5: mu(v) = 0.3 (0.6 exp(-30 v / (m/s)) + 0.4)."""
CORRUGATION = rc.Harmonic.from_wavelength(0.015, 5e-6)
"""Figure 3's surface: wavelength 15 mm, amplitude 5 um, a crest at X = 0."""
AXIS_POSITION = 0.3 * 0.015
"""x_c [m] of figure 3: the axis stands 4.5 mm past a crest, on the flank."""
SPIKE_NODES = 128
"""Chebyshev nodes of the slip iteration in the full figure 5.  The default (16) is set for 1e-3 in T', not for the
spike: q/p peaks at 0.281 with 16 nodes and 0.287 with 128 (smooth); the exact peak is mu_s = 0.3, where the slip
starts from zero.  From 192 nodes on the peak is higher (0.299) but q/p ripples by ~1 % behind it."""
DPI = 150

DASHED = {"linestyle": "--", "color": "0.35"}
"""Carter's closed form, as in the paper."""
SOLID = {"linestyle": "-", "color": "C0", "linewidth": 1.8}
"""rollcontact's solution."""


class Rendered(NamedTuple):
    """What a figure function returns.

    Attributes
    ----------
    path : Path
        The PNG written.
    numbers : dict
        Key numbers of the figure (SI units, named with their unit where not [1]).
    """

    path: Path
    numbers: dict


def contact_modulus() -> float:
    """E* [Pa] of :data:`MATERIAL`."""
    return MATERIAL.contact_modulus


def hertz_patch() -> tuple[float, float]:
    """Hertz half-width a [m] and peak pressure p0 [Pa] of the common case."""
    return rc.hertz(LOAD, RADIUS, contact_modulus())


def saturation_creep() -> float:
    """Carter's full-slip creep mu a / R [1] of the common case."""
    return MU * hertz_patch()[0] / RADIUS


def scene(creep: float, **changes) -> rc.Scene:
    """The common case at a creep [1], with other Scene fields changed."""
    return rc.Scene(LOAD, creep=creep, radius=RADIUS, material=MATERIAL, friction=rc.Coulomb(MU), **changes)


def new_figure(width: float, height: float) -> Figure:
    """A matplotlib Figure on the Agg canvas (no pyplot, no global state), size in inches."""
    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save(fig: Figure, out: Path, name: str) -> Path:
    """Write ``fig`` as ``out/name`` and return the path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.savefig(path, dpi=DPI)
    return path


def patch_points(result: rc.ContactResult, count: int, margin: float = 1e-3) -> np.ndarray:
    """``count`` positions x [m] inside the patch, ``margin`` half-widths clear of its edges (p > 0 there)."""
    a = result.contact_half_width
    return np.linspace(result.leading_edge + margin * a, result.trailing_edge - margin * a, count)


def integral(values: np.ndarray, x: np.ndarray) -> float:
    """Trapezoidal integral of samples over x."""
    return float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(x)))


# ------------------------------------------------------------------------------------------------------ figure 2
def figure_2(out: Path = HERE, quick: bool = False) -> Rendered:
    """Carter's creep curve T'(xi) (paper Fig. 2), checked against rollcontact's discretised solver.

    Parameters
    ----------
    out : Path
        Directory of the PNG.
    quick : bool
        Few points (smoke test).

    Returns
    -------
    Rendered
        ``fig2_carter_creep_curve.png``; numbers: ``saturation_creep``, ``saturated_ratio`` (T'/(mu N') at the
        largest creep), ``initial_slope_ratio`` (dT'/dxi at xi -> 0 over pi E* a / 2), ``monotone``,
        ``discretised_error`` (max |T'_disc - T'_Carter| / (mu N')), ``max_ratio`` (max T'/(mu N')).
    """
    sat = saturation_creep()
    a = hertz_patch()[0]
    creeps = np.linspace(0.0, 2.0 * sat, 21 if quick else 241)
    force = np.array([rc.solve(scene(float(c))).tangential_force_per_length for c in creeps])
    checks = np.linspace(0.1, 1.9, 3 if quick else 10) * sat
    disc = np.array([rc.solve(scene(float(c)), method="discretised").tangential_force_per_length for c in checks])
    carter_at_checks = np.array([rc.carter(LOAD, float(c), RADIUS, contact_modulus(), MU)[0] for c in checks])
    small = 1e-6 * sat
    slope = rc.carter(LOAD, small, RADIUS, contact_modulus(), MU)[0] / small

    fig = new_figure(6.4, 4.2)
    ax = fig.add_subplot()
    ax.plot(creeps, force / 1e3, **SOLID, label="Carter, rollcontact closed form")
    ax.plot(checks, disc / 1e3, "o", color="C1", mfc="none", label="rollcontact discretised solver")
    ax.axhline(MU * LOAD / 1e3, **DASHED, linewidth=1.0, label=r"Coulomb limit $\mu N'$")
    ax.axvline(sat, color="0.6", linestyle=":", linewidth=1.0)
    ax.annotate(r"full slip, $\xi = \mu a / R$", (sat, 0.3 * MU * LOAD / 1e3), xytext=(6, 0),
                textcoords="offset points", fontsize=9, color="0.3")
    ax.set_xlabel(r"creep $\xi$ [1]")
    ax.set_ylabel(r"tangential force per length $T'$ [kN/m]")
    ax.set_xlim(0.0, creeps[-1])
    ax.set_ylim(0.0, 1.15 * MU * LOAD / 1e3)
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, -3))
    ax.legend(loc="lower right", fontsize=9)
    ax.set_title("after Nielsen, Fig. 2: creep curve of Carter\n"
                 rf"$N'$ = {LOAD / 1e6:g} MN/m, $R$ = {RADIUS} m, $\mu$ = {MU}, $a$ = {a * 1e3:.2f} mm", fontsize=10)
    path = save(fig, out, "fig2_carter_creep_curve.png")
    return Rendered(path, {
        "saturation_creep": sat,
        "saturated_ratio": float(force[-1] / (MU * LOAD)),
        "max_ratio": float(force.max() / (MU * LOAD)),
        "initial_slope_ratio": slope / (math.pi * contact_modulus() * a / 2.0),
        "monotone": bool(np.all(np.diff(force) >= 0.0)),
        "discretised_error": float(np.abs(disc - carter_at_checks).max() / (MU * LOAD)),
    })


# ------------------------------------------------------------------------------------------------------ figure 3
def figure_3(out: Path = HERE, quick: bool = False) -> Rendered:
    """Traction on a corrugated surface by the polynomial method vs Carter, and the cylinder on the surface
    (paper Fig. 3).

    Parameters
    ----------
    out : Path
        Directory of the PNG.
    quick : bool
        Few points (smoke test).

    Returns
    -------
    Rendered
        ``fig3_corrugation.png``; numbers: ``success``, ``force`` and ``carter_force`` [N/m], ``half_width``,
        ``carter_half_width``, ``offset`` and ``stick_half_width`` [m], ``bound_excess`` (max (|q| - mu p) over
        mu p0, <= 0 when admissible), ``force_integral_error`` and ``load_integral_error`` (relative misfit of
        the integrals of q and p against T' and N'), ``max_traction_difference`` (max |q - q_Carter| / (mu p0)).
    """
    creep = 0.45 * saturation_creep()
    surface = rc.Surface(harmonics=(CORRUGATION,))
    result = rc.solve(scene(creep, surface=surface, axis_position=AXIS_POSITION), method="polynomial")
    carter = rc.solve(scene(creep), method="closed_form")
    x_c = AXIS_POSITION
    a, p0 = result.contact_half_width, result.max_pressure
    span = 1.25 * max(a + abs(result.contact_offset), carter.contact_half_width)
    x = np.linspace(-span, span, 201 if quick else 2001)
    inside = patch_points(result, 201 if quick else 4001)
    q_in, p_in = result.traction(inside), result.pressure(inside)

    fig = new_figure(6.4, 6.0)
    top, bottom = fig.subplots(2, 1, height_ratios=(3, 2))
    top.plot(x * 1e3, carter.traction(x) / 1e6, **DASHED, label=f"Carter (smooth surface), T' = "
             f"{carter.tangential_force_per_length / 1e3:.0f} kN/m")
    top.plot(x * 1e3, result.traction(x) / 1e6, **SOLID, label=f"polynomial method, T' = "
             f"{result.tangential_force_per_length / 1e3:.0f} kN/m")
    top.plot(x * 1e3, MU * result.pressure(x) / 1e6, color="C0", linewidth=0.8, linestyle=":",
             label=r"$\mu p$ (polynomial method)")
    boundary = result.leading_edge + 2.0 * result.stick_half_width
    top.axvline(boundary * 1e3, color="C0", linewidth=0.6, alpha=0.5)
    top.annotate("stick | slip", (boundary * 1e3, 0.02 * MU * p0 / 1e6), xytext=(3, 0), textcoords="offset points",
                 fontsize=8, color="C0")
    top.set_xlim(-span * 1e3, span * 1e3)
    top.set_ylim(0.0, 1.25 * MU * max(p0, carter.max_pressure) / 1e6)
    top.set_xlabel(r"$x = X - x_c$, from the axis projection [mm] (material flows in +x)")
    top.set_ylabel(r"tangential stress $q$ [MPa]")
    top.legend(loc="upper left", fontsize=8)

    wavelength = 2.0 * math.pi / CORRUGATION.wavenumber
    X = np.linspace(x_c - 1.2 * wavelength, x_c + 1.2 * wavelength, 301 if quick else 3001)
    z = surface.height(X)
    edges = np.array([result.leading_edge, result.trailing_edge]) + x_c
    lift = float(np.mean(surface.height(edges) - (edges - x_c) ** 2 / (2.0 * RADIUS)))
    cylinder = lift + (X - x_c) ** 2 / (2.0 * RADIUS)
    bottom.plot(X * 1e3, z * 1e6, color="k", linewidth=1.4, label=r"surface $Z(X)$")
    bottom.plot(X * 1e3, cylinder * 1e6, color="C0", linewidth=1.2, label="cylinder (undeformed)")
    bottom.axvspan(edges[0] * 1e3, edges[1] * 1e3, color="C0", alpha=0.15, label="contact patch")
    bottom.axvline(x_c * 1e3, color="0.3", linestyle="-.", linewidth=0.8)
    bottom.annotate(r"axis $x_c$", (x_c * 1e3, 1.6 * CORRUGATION.amplitude * 1e6), xytext=(3, 0),
                    textcoords="offset points", fontsize=8)
    bottom.set_xlim(X[0] * 1e3, X[-1] * 1e3)
    bottom.set_ylim(-2.0 * CORRUGATION.amplitude * 1e6, 4.0 * CORRUGATION.amplitude * 1e6)
    bottom.set_xlabel(r"surface coordinate $X$ [mm]")
    bottom.set_ylabel(r"height [$\mu$m]")
    bottom.legend(loc="upper right", fontsize=8, ncol=3)
    fig.suptitle("after Nielsen, Fig. 3: tangential stress on a corrugated surface (top), the cylinder on it (bottom)\n"
                 rf"wavelength {wavelength * 1e3:g} mm, amplitude {CORRUGATION.amplitude * 1e6:g} $\mu$m, "
                 rf"$x_c$ = {x_c * 1e3:g} mm, $\xi$ = {creep:.2e}, $N'$ = {LOAD / 1e6:g} MN/m, $\mu$ = {MU}",
                 fontsize=9)
    path = save(fig, out, "fig3_corrugation.png")
    return Rendered(path, {
        "success": bool(result.success and carter.success),
        "force": result.tangential_force_per_length,
        "carter_force": carter.tangential_force_per_length,
        "half_width": a,
        "carter_half_width": carter.contact_half_width,
        "offset": result.contact_offset,
        "stick_half_width": result.stick_half_width,
        "bound_excess": float(np.max(np.abs(q_in) - MU * p_in) / (MU * p0)),
        "force_integral_error": abs(integral(q_in, inside) / result.tangential_force_per_length - 1.0),
        "load_integral_error": abs(integral(p_in, inside) / LOAD - 1.0),
        "max_traction_difference": float(np.abs(result.traction(x) - carter.traction(x)).max() / (MU * p0)),
    })


# ------------------------------------------------------------------------------------------------------ figure 4
def falling_scene(creep: float) -> rc.Scene:
    """The common case with :data:`FALLING` friction at :data:`SPEED`."""
    return scene(creep).replace(friction=FALLING, rolling_speed=SPEED)


def falling_coefficient(creep: float) -> float:
    """T'/N' [1] of the falling-friction case at a creep (NaN when the solve fails)."""
    result = rc.solve(falling_scene(creep))
    return result.traction_coefficient if result.success else math.nan


def figure_4(out: Path = HERE, quick: bool = False) -> Rendered:
    """Velocity-dependent friction law and the creep curve it gives, with its maximum (paper Fig. 4).

    Parameters
    ----------
    out : Path
        Directory of the PNG.
    quick : bool
        Few points (smoke test).

    Returns
    -------
    Rendered
        ``fig4_falling_friction_creep_curve.png``; numbers: ``success`` (every solve), ``mu_static``,
        ``peak_creep``, ``peak_coefficient`` (the maximum of T'/N'), ``last_creep``, ``last_coefficient``,
        ``last_friction`` (mu(V xi) at the last creep), ``rises_to_peak``, ``falls_after_peak`` (monotone on the
        sampled curve either side of the maximum).
    """
    sat = saturation_creep()
    creeps = np.linspace(0.02, 6.0, 16 if quick else 300) * sat
    coefficients = np.array([falling_coefficient(float(c)) for c in creeps])
    i = int(np.nanargmax(coefficients))
    lo, hi = creeps[max(i - 1, 0)], creeps[min(i + 1, creeps.size - 1)]
    peak = optimize.minimize_scalar(lambda c: -falling_coefficient(c), bounds=(lo, hi), method="bounded",
                                    options={"xatol": 1e-4 * sat})
    peak_creep, peak_coefficient = float(peak.x), -float(peak.fun)
    dense = np.linspace(0.0, creeps[-1], 400)
    mu_curve = FALLING.coefficient(SPEED * dense)
    carter_curve = np.array([rc.carter(LOAD, float(c), RADIUS, contact_modulus(), MU)[0] for c in dense]) / LOAD

    fig = new_figure(6.4, 4.4)
    ax = fig.add_subplot()
    ax.plot(dense, mu_curve, **DASHED, zorder=3, label=r"friction law $\mu(V\xi)$, slip velocity $V\xi$")
    ax.plot(creeps, coefficients, **SOLID, label=r"creep curve $T'/N'$ (polynomial method)")
    ax.plot(dense, carter_curve, color="0.6", linestyle=":", linewidth=1.0,
            label=rf"Carter with constant $\mu$ = {MU}")
    ax.plot([peak_creep], [peak_coefficient], "o", color="C3", zorder=5)
    ax.annotate(rf"maximum {peak_coefficient:.3f} at $\xi$ = {peak_creep:.2e}", (peak_creep, peak_coefficient),
                xytext=(12, 10), textcoords="offset points", fontsize=9, color="C3")
    ax.set_xlim(0.0, creeps[-1])
    ax.set_ylim(0.0, 1.15 * MU)
    ax.set_xlabel(r"creep $\xi$ [1]")
    ax.set_ylabel(r"friction coefficient $\mu$, traction coefficient $T'/N'$ [1]")
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, -3))
    top = ax.secondary_xaxis("top", functions=(lambda c: SPEED * c, lambda v: v / SPEED))
    top.set_xlabel(r"slip velocity $V\xi$ [m/s]")
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title("after Nielsen, Fig. 4: velocity-dependent friction (dashed) and its creep curve (solid)\n"
                 rf"$\mu(v)$ = {MU} (0.6 exp($-v \cdot$ {FALLING.decay:g} s/m) + 0.4), $V$ = {SPEED:g} m/s, "
                 rf"$N'$ = {LOAD / 1e6:g} MN/m", fontsize=9)
    path = save(fig, out, "fig4_falling_friction_creep_curve.png")
    before, after = coefficients[: i + 1], coefficients[i:]
    return Rendered(path, {
        "success": bool(np.all(np.isfinite(coefficients)) and peak.success),
        "mu_static": FALLING.static_coefficient,
        "peak_creep": peak_creep,
        "peak_coefficient": peak_coefficient,
        "sampled_peak_index": i,
        "samples": int(creeps.size),
        "last_creep": float(creeps[-1]),
        "last_coefficient": float(coefficients[-1]),
        "last_friction": float(FALLING.coefficient(SPEED * creeps[-1])),
        "rises_to_peak": bool(np.all(np.diff(before) > 0.0)),
        "falls_after_peak": bool(np.all(np.diff(after) < 0.0)),
    })


# ------------------------------------------------------------------------------------------------------ figure 5
def figure_5(out: Path = HERE, quick: bool = False) -> Rendered:
    """Traction with falling friction vs Carter: the spike at the stick/slip boundary (paper Fig. 5).

    The friction law is that of figure 4.  At the boundary the slip is zero, so q/p reaches mu_s there and falls
    steeply behind it as the slip (and with it the velocity) grows: a spike of width ~ the node spacing of the
    slip iteration, which the full gallery resolves with :data:`SPIKE_NODES` nodes.

    Parameters
    ----------
    out : Path
        Directory of the PNG.
    quick : bool
        Few points and the default nodes of the polynomial method (smoke test).

    Returns
    -------
    Rendered
        ``fig5_stick_slip_spike.png``; numbers: ``success``, ``creep``, ``boundary`` and ``spike_position`` [m]
        (stick/slip boundary and the x of max q/p), ``half_width`` [m], ``spike_ratio`` (max q/p),
        ``trailing_ratio`` (q/p next to the trailing edge), ``mu_static``, ``bound_ratio`` (max |q| / (mu(V|s|) p)
        over the patch, 1 at the nodes of the slip iteration, a few per cent above it between them next to the
        boundary), ``carter_max_ratio`` (max q/p of Carter, = mu in its slip zone), ``force`` and ``carter_force``
        [N/m].
    """
    creep = 0.4 * saturation_creep()
    options = {} if quick else {"nodes": SPIKE_NODES}
    result = rc.solve(falling_scene(creep), method="polynomial", **options)
    carter = rc.solve(scene(creep), method="closed_form")
    a, p0 = result.contact_half_width, result.max_pressure
    x = np.linspace(-1.1 * a, 1.1 * a, 401 if quick else 8001) + result.contact_offset
    inside = patch_points(result, 401 if quick else 8001, margin=2e-3)
    q, p, s = result.traction(inside), result.pressure(inside), result.slip(inside)
    ratio = q / p
    j = int(np.argmax(ratio))
    boundary = result.leading_edge + 2.0 * result.stick_half_width
    mu_local = FALLING.coefficient(SPEED * np.abs(np.nan_to_num(s)))
    q_c, p_c = carter.traction(inside), carter.pressure(inside)

    fig = new_figure(6.4, 6.4)
    top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    scale = MU * p0
    top.plot(x * 1e3, carter.traction(x) / scale, **DASHED, label=rf"Carter, constant $\mu$ = {MU}")
    top.plot(x * 1e3, result.traction(x) / scale, **SOLID, label=r"polynomial method, falling $\mu(V|s|)$")
    top.plot(x * 1e3, result.pressure(x) / p0, color="0.6", linestyle=":", linewidth=1.0,
             label=r"$p / p_0$ (bound $|q| \leq \mu_s p$)")
    top.plot([inside[j] * 1e3], [q[j] / scale], "o", color="C3", markersize=4, zorder=5)
    top.set_ylim(0.0, 1.45)
    top.set_ylabel(r"$q / (\mu_s p_0)$ [1]")
    top.legend(loc="upper left", fontsize=8)
    bottom.plot(inside * 1e3, q_c / p_c, **DASHED, label=r"Carter $q/p$")
    bottom.plot(inside * 1e3, ratio, **SOLID, label=r"polynomial method $q/p$")
    bottom.plot(inside * 1e3, mu_local, color="C1", linestyle="-.", linewidth=1.0,
                label=r"$\mu(V|s|)$ from the computed slip")
    bottom.plot([inside[j] * 1e3], [ratio[j]], "o", color="C3", markersize=4, zorder=5)
    bottom.annotate(rf"spike $q/p$ = {ratio[j]:.3f} ($\to \mu_s$ where $s \to 0$)", (inside[j] * 1e3, ratio[j]),
                    xytext=(8, 14), va="bottom",
                    textcoords="offset points", fontsize=9, color="C3")
    bottom.set_ylim(0.0, 1.25 * MU)
    bottom.set_ylabel(r"local coefficient $q/p$ [1]")
    bottom.set_xlabel(r"$x$ from the axis projection [mm] (material flows in +x, leading edge left)")
    bottom.legend(loc="lower right", fontsize=8)
    for ax in (top, bottom):
        ax.axvline(boundary * 1e3, color="C0", linewidth=0.6, alpha=0.5)
        ax.set_xlim(x[0] * 1e3, x[-1] * 1e3)
    top.annotate("stick", (0.5 * (result.leading_edge + boundary) * 1e3, 1.02), ha="center", fontsize=9)
    top.annotate("slip", (0.5 * (result.trailing_edge + boundary) * 1e3, 1.02), ha="center", fontsize=9)
    fig.suptitle("after Nielsen, Fig. 5: normalised tangential stress, Carter (dashed) vs falling friction (solid)\n"
                 rf"friction law of Fig. 4, $V$ = {SPEED:g} m/s, $\xi$ = {creep:.2e}, $p_0$ = {p0 / 1e6:.0f} MPa",
                 fontsize=9)
    path = save(fig, out, "fig5_stick_slip_spike.png")
    return Rendered(path, {
        "success": bool(result.success and carter.success),
        "creep": creep,
        "half_width": a,
        "boundary": boundary,
        "spike_position": float(inside[j]),
        "spike_ratio": float(ratio[j]),
        "trailing_ratio": float(ratio[-1]),
        "mu_static": FALLING.static_coefficient,
        "bound_ratio": float(np.max(np.abs(q) / (mu_local * p))),
        "carter_max_ratio": float(np.max(q_c / p_c)),
        "force": result.tangential_force_per_length,
        "carter_force": carter.tangential_force_per_length,
    })


# ------------------------------------------------------------------------------------------------------ figure 6
def figure_6(out: Path = HERE, quick: bool = False) -> Rendered:
    """Traction under an oscillating tangential force vs the equivalent Carter field (paper Fig. 6).

    The force ``T'(sigma) = mu N' (0.4 + 0.2 sin(2 pi sigma / lambda))`` oscillates over a rolled wavelength
    lambda = 5 a (instationary: the paper's rule of thumb asks lambda/a > 20 for stationarity).  The traction by
    the paper's travelling-wave route is drawn at four phases against Carter's at the same instantaneous force.

    Parameters
    ----------
    out : Path
        Directory of the PNG.
    quick : bool
        Few phases and harmonics (smoke test).

    Returns
    -------
    Rendered
        ``fig6_instationary.png``; numbers: ``success`` (every phase), ``wavelength_over_a``, ``max_residual``
        (force misfit over mu N'), ``bound_excess`` (max (|q| - mu p) over mu p0), ``deviation`` (L2 deviation of
        the oscillating part from quasi-steady Carter) and ``deviation_rule`` (2.5 a / lambda),
        ``max_difference`` (max |q - q_Carter| / (mu p0) at the drawn phases).
    """
    a, p0 = hertz_patch()
    limit = MU * LOAD
    force = OscillatingForce(0.4 * limit, 0.2 * limit, 5.0 * a)
    phases = 4 if quick else 16
    options = {"harmonics": 4, "order": 20} if quick else {}
    results = oscillating_force_chebyshev(LOAD, force, radius=RADIUS, contact_modulus=contact_modulus(), mu=MU,
                                          phases=phases, **options)
    x = np.linspace(-1.1 * a, 1.1 * a, 241 if quick else 2001)
    inside = np.linspace(-0.999 * a, 0.999 * a, 401 if quick else 4001)
    shown = [results[k * phases // 4] for k in range(4)]

    fig = new_figure(6.4, 6.0)
    cycle, ax = fig.subplots(2, 1, height_ratios=(1, 3))
    sigma = np.linspace(0.0, 1.0, 200)
    cycle.plot(sigma, force.at_phase(sigma) / 1e3, color="k", linewidth=1.0)
    differences, excess = [], []
    for k, r in enumerate(shown):
        phase, t = r.info["phase"], r.tangential_force_per_length
        a_star = a * math.sqrt(1.0 - t / limit)
        creep = MU * (a - a_star) / RADIUS
        reference = CarterDistributions(a, p0, a_star, 0.0, MU, creep, RADIUS)
        colour = f"C{k}"
        cycle.plot([phase], [t / 1e3], "o", color=colour)
        ax.plot(x * 1e3, r.traction(x) / 1e6, color=colour, linewidth=1.8,
                label=rf"$\sigma/\lambda$ = {phase:.2f}, $T'$ = {t / 1e3:.0f} kN/m")
        ax.plot(x * 1e3, reference.traction(x) / 1e6, color=colour, linestyle="--", linewidth=1.0)
        differences.append(np.abs(r.traction(x) - reference.traction(x)).max() / (MU * p0))
    for r in results:
        excess.append(float(np.max(np.abs(r.traction(inside)) - MU * r.pressure(inside)) / (MU * p0)))
    phase_legend = ax.legend(loc="upper left", fontsize=8)
    ax.add_artist(phase_legend)
    styles = [ax.plot([], [], color="k", label="instationary (travelling wave)")[0],
              ax.plot([], [], color="k", linestyle="--", linewidth=1.0,
                      label="Carter at the same $T'$\n(phases 0 and 0.50 share it)")[0],
              ax.plot(x * 1e3, MU * shown[0].pressure(x) / 1e6, color="0.6", linestyle=":", linewidth=1.0,
                      label=r"$\mu p$")[0]]
    ax.legend(handles=styles, loc="upper right", fontsize=8)
    cycle.set_xlim(0.0, 1.0)
    cycle.set_xlabel(r"rolled distance over wavelength $\sigma/\lambda$ [1]")
    cycle.set_ylabel(r"$T'$ [kN/m]")
    ax.set_xlim(x[0] * 1e3, x[-1] * 1e3)
    ax.set_ylim(0.0, 1.45 * MU * p0 / 1e6)
    ax.set_xlabel(r"$x$ from the axis projection [mm] (material flows in +x, leading edge left)")
    ax.set_ylabel(r"tangential stress $q$ [MPa]")
    fig.suptitle("after Nielsen, Fig. 6: tangential stress of an instationary contact (solid) vs Carter (dashed)\n"
                 rf"$T' = \mu N'$ (0.4 + 0.2 sin 2$\pi\sigma/\lambda$), "
                 rf"$\lambda$ = 5a = {force.wavelength * 1e3:.1f} mm, $N'$ = {LOAD / 1e6:g} MN/m, $\mu$ = {MU}",
                 fontsize=9)
    path = save(fig, out, "fig6_instationary.png")
    return Rendered(path, {
        "success": all(r.success for r in results),
        "wavelength_over_a": force.wavelength / a,
        "max_residual": max(r.residual for r in results),
        "bound_excess": max(excess),
        "deviation": quasi_steady_deviation(results, force.mean, radius=RADIUS, contact_modulus=contact_modulus(),
                                            mu=MU),
        "deviation_rule": 2.5 * a / force.wavelength,
        "max_difference": float(max(differences)),
    })


ELLIPSE = {"a": 5e-3, "b": 7e-3, "load": 80e3}
"""Figure 7's contact: semi-axes a = 5 mm (rolling direction), b = 7 mm, Fn = 80 kN, steel, mu = 0.3."""


def figure_7(out: Path = HERE, quick: bool = False) -> Rendered:
    """Elliptic contact: the traction of a spin case by the discretised 3D method, beside each level's creep curve.

    Left: stick and slip areas and the traction vectors of xi at 0.3 and phi at 0.6 of their saturation creepages
    (where Kalker's linear theory reaches mu Fn).  Right: the lateral force of pure spin, Fy/(mu Fn) against phi,
    by every elliptic level (linear theory, FASTSIM, strips, discretised).

    Parameters
    ----------
    out : Path
        Directory of the PNG.
    quick : bool
        Coarse grid and few creepages (smoke test).

    Returns
    -------
    Rendered
        ``fig7_elliptic_contact.png``; numbers: ``success`` (every solve), ``bound_excess`` (max (|q| - mu p) over
        mu p0), ``stick_fraction``, ``leading_stick`` (share of the stick area ahead of the centre, x > 0),
        ``largest_force`` (max |F|/(mu Fn) on the discretised curve), ``level_gaps`` (per level, the largest
        |Fy| difference to the discretised curve over mu Fn, beyond the linear range).
    """
    e = ELLIPSE
    base = rc.EllipticScene.from_semi_axes(e["load"], e["a"], e["b"], material=MATERIAL, friction=MU)
    c, g = base.hertz.c, base.shear_modulus
    coefficients = rc.creepage_coefficients(base.hertz.aspect_ratio, MATERIAL.poisson_ratio)
    xi_sat = MU * e["load"] / (g * c * c * coefficients.c11)
    phi_sat = MU * e["load"] / (g * c**3 * coefficients.c23)
    elements = 20 if quick else 48
    spin = rc.solve_elliptic(base.replace(longitudinal_creepage=0.3 * xi_sat, spin_creepage=0.6 * phi_sat),
                             "discretised", elements=elements, extrapolate=False, fields=True)
    f = spin.fields
    contact = f.pressure > 0.0
    p0 = f.pressure.max()

    fig = new_figure(11.0, 4.6)
    left, right = fig.subplots(1, 2, width_ratios=(1.0, 1.15))
    theta = np.linspace(0.0, 2.0 * math.pi, 200)
    left.plot(e["a"] * 1e3 * np.cos(theta), e["b"] * 1e3 * np.sin(theta), color="k", linewidth=1.0)
    dx, dy = (f.x[1, 0] - f.x[0, 0]) * 1e3, (f.y[0, 1] - f.y[0, 0]) * 1e3
    for mask, colour, label in ((f.stick & contact, "0.75", "stick"), (contact & ~f.stick, "#fde2c4", "slip")):
        for x, y in zip(f.x[mask] * 1e3, f.y[mask] * 1e3, strict=True):
            left.add_patch(Rectangle((x - dx / 2, y - dy / 2), dx, dy, color=colour, linewidth=0))
        left.plot([], [], "s", color=colour, label=label)
    step = max(1, elements // 16)
    sub = (slice(None, None, step), slice(None, None, step))
    show = contact[sub]
    left.quiver(f.x[sub][show] * 1e3, f.y[sub][show] * 1e3, f.traction_x[sub][show] / (MU * p0),
                f.traction_y[sub][show] / (MU * p0), angles="xy", scale_units="xy", scale=1.0 / (2.2 * dx * step),
                width=0.004, color="C0", label=r"$q$ (on the rail)")
    left.annotate("", xy=(e["a"] * 1.25e3, 0.0), xytext=(e["a"] * 0.95e3, 0.0),
                  arrowprops={"arrowstyle": "->", "color": "k"})
    left.text(e["a"] * 1.1e3, 0.4, "rolling", ha="center", fontsize=8)
    left.set_aspect("equal")
    left.set_xlim(-1.3 * e["a"] * 1e3, 1.35 * e["a"] * 1e3)
    left.set_xlabel("x [mm] (the wheel rolls towards +x: leading edge right)")
    left.set_ylabel("y [mm]")
    left.legend(loc="lower left", fontsize=7)
    left.set_title(rf"discretised: $\xi$ = 0.3 $\xi_s$, $\phi$ = 0.6 $\phi_s$; "
                   rf"$F/\mu F_n$ = ({spin.force_coefficients[0]:.2f}, {spin.force_coefficients[1]:.2f})",
                   fontsize=9)

    levels = ("linear", "fastsim", "strips", "discretised")
    phis = np.linspace(0.0, 3.0, 5 if quick else 16)[1:] * phi_sat
    curves, success = {}, spin.success
    for level in levels:
        options = {"elements": elements} if level == "discretised" else {}
        results = [rc.solve_elliptic(base.replace(spin_creepage=phi), level, **options) for phi in phis]
        success = success and all(r.success for r in results)
        curves[level] = np.array([r.force_coefficients[1] for r in results])
        style = {"color": "k", "linewidth": 2.0} if level == "discretised" else {"linewidth": 1.2}
        right.plot(phis / phi_sat, curves[level], "o-" if level == "discretised" else "-", label=level,
                   markersize=3, **style)
    right.set_ylim(0.0, 1.1)
    right.set_xlabel(r"spin creepage $\phi / \phi_s$ ($\phi_s$: linear $F_y = \mu F_n$)")
    right.set_ylabel(r"$F_y / (\mu F_n)$")
    right.legend(fontsize=8)
    right.set_title("pure spin: the lateral force of each level", fontsize=9)
    fig.suptitle(f"Elliptic contact a = {e['a'] * 1e3:g} mm, b = {e['b'] * 1e3:g} mm, Fn = {e['load'] / 1e3:g} kN, "
                 f"mu = {MU}", fontsize=10)
    path = save(fig, out, "fig7_elliptic_contact.png")
    beyond = phis > phi_sat
    stick = f.stick & contact
    return Rendered(path, {
        "success": success,
        "bound_excess": float(np.max(f.traction_magnitude[contact] - MU * f.pressure[contact]) / (MU * p0)),
        "stick_fraction": float(stick.sum() / contact.sum()),
        "leading_stick": float((stick & (f.x > 0)).sum() / max(stick.sum(), 1)),
        "largest_force": float(np.abs(curves["discretised"]).max()),
        "level_gaps": {level: float(np.abs(curves[level] - curves["discretised"])[beyond].max())
                       for level in levels if level != "discretised"},
    })


FIGURES = {2: figure_2, 3: figure_3, 4: figure_4, 5: figure_5, 6: figure_6, 7: figure_7}
"""The gallery, by the paper's figure number (7: the elliptic contact, beyond the paper)."""


def make_all(out: Path = HERE, quick: bool = False) -> dict[int, Rendered]:
    """Draw every figure of :data:`FIGURES` into ``out`` with a progress bar (on a terminal).

    Parameters
    ----------
    out : Path
        Directory of the PNGs (created when missing).
    quick : bool
        Few points.

    Returns
    -------
    dict
        Figure number -> :class:`Rendered`.
    """
    rendered = {}
    with Progress(len(FIGURES), "figures") as progress:
        for number, function in FIGURES.items():
            progress.advance(0, f"figure {number}")
            rendered[number] = function(Path(out), quick)
            progress.advance(1, f"figure {number} done")
    return rendered


def main(argv=None) -> int:
    """Command line: ``python docs/figures/make_figures.py [--quick] [--out DIR]``."""
    parser = argparse.ArgumentParser(description="Reproduce figures 2-6 of Nielsen's paper with rollcontact, and "
                                                 "figure 7 (the elliptic contact).")
    parser.add_argument("--quick", action="store_true", help="few points (seconds; for the smoke tests)")
    parser.add_argument("--out", type=Path, default=HERE, help=f"output directory (default {HERE})")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    rendered = make_all(args.out, args.quick)
    for number, (path, _) in rendered.items():
        print(f"figure {number}: {path}")
    print(f"{len(rendered)} figures in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
