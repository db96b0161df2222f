"""Tangential contact of a patch by the strips of its normal solution (docs/physics-wheelrail-patches.md, "The
strips' tangential problem"): the elliptic strips (:mod:`rollcontact.elliptic.methods.strips`, docs/physics.md,
"Strips") on general strips.

Each strip j of :func:`~rollcontact.wheelrail.methods.strip_normal.strip_normal` carries the semi-elliptic pressure
``p = q_j sqrt(a_j^2 - x^2)`` (``q_j = p0_j / a_j``) and solves its 2D rolling problem as the elliptic strips do: the
stick zone at the leading edge ``[2 d - a_j, a_j]`` in closed form, the slip zones at ``mu p`` along the slip, with
the slip directions of spin from a FASTSIM march.  On an ellipse ``q_j`` is the same on every strip; here each strip
takes its own in the slip length ``1 / (2 mu q_j)`` and the scaled spin ``psi_j = phi E_phi / (2 mu q_j)``.

A run of strips in contact (a lobe) takes the constants that the elliptic strips take from their ellipse from an
equivalent ellipse (the stated rule): its area is the lobe's, ``2 sum_j w_j a_j``, and its a/b that of the Hertz
ellipse whose strips are stiffened as the lobe's are, ``F(a/b) = k``, where ``k`` is the lobe's load-weighted mean
of ``q_j / (E* A_j)`` and ``F(a/b) = p0 / (a E* A)`` Hertz's ratio (1 in the strip limit, 4/pi on a circle;
:func:`stiffening_ratio`).  On a Hertzian patch this is its own ellipse.  Its Kalker coefficients give the moduli
``E_x = 4 G C11 / pi^2``, ``E_y = 4 G C22 / pi^2``, ``E_phi = 3 G C23 sqrt(b/a) / pi``, the moment ratio r that keeps
C33 (about the lobe's centroid ``s_L``, so that the lobe sees the longitudinal creepage ``xi - phi s_L`` and spin
about its centroid), the short strips' stiffening ``f_j = K (a_j / a_max)^(-gamma)`` (``(1 - y^2/b^2)^(-gamma/2)``
on an ellipse, K keeping ``sum w a f = sum w a``), the lateral force's cross influence and the march's
flexibilities.  ``Mz`` is taken about the rigid contact point, ``s = 0``.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from rollcontact.core.materials import Material
from rollcontact.elliptic.creep_coefficients import aspect_ratio_range, extended_creepage_coefficients
from rollcontact.elliptic.hertz import differences
from rollcontact.elliptic.methods.common import friction_kernel, march, march_slips, slips_at
from rollcontact.elliptic.methods.strips import (
    CROSS_ITERATIONS,
    FALLING_PASSES,
    SPIN_FLEXIBILITY,
    STICK_FADE,
    STIFFENING_SCALE,
    TINY,
    cells,
    cross_coefficients,
    elastic_slips,
    gauss,
    march_flexibilities,
)
from rollcontact.elliptic.result import TractionField
from rollcontact.wheelrail.methods.strip_normal import StripContact

DEFAULT_STEPS = 20
"""Cells along each strip of the march (with spin, or for the fields)."""


def stiffening_ratio(ratio):
    """Hertz's ``F(a/b) = p0 / (a E* A)`` [1] (A the gap's curvature along a): ``(a/b) e^2 / (K - E)`` for
    ``a >= b`` (``e^2 = 1 - b^2/a^2``), ``e^2 / (E - (a/b)^2 K)`` below (``e^2 = 1 - a^2/b^2``); 1 in the strip limit
    a/b -> 0, 4/pi on a circle (docs/physics.md, "Hertz's ellipse")."""
    if ratio >= 1.0:
        m = -math.expm1(-2.0 * math.log(ratio))
        return ratio / differences(m)[0]
    m = -math.expm1(2.0 * math.log(ratio))
    return 1.0 / (ratio * ratio * differences(m)[1])


@lru_cache(maxsize=1)
def _ratio_table() -> tuple[np.ndarray, np.ndarray]:
    logs = np.linspace(math.log(1e-3), math.log(1e3), 1201)
    values = np.array([stiffening_ratio(math.exp(v)) for v in logs])
    return np.log(values), logs


def equivalent_ratio(stiffening: float) -> float:
    """The a/b [1] whose Hertz ratio :func:`stiffening_ratio` is ``stiffening`` (>= 1; interpolated in logs over
    a/b 1e-3 .. 1e3, held at the ends)."""
    log_values, logs = _ratio_table()
    return math.exp(float(np.interp(math.log(max(stiffening, 1.0)), log_values, logs)))


@lru_cache(maxsize=256)
def _spread_shape(gamma: float) -> float:
    nodes, weights, root = gauss(64)
    shape = root ** (-gamma)
    factor = float(weights @ root) / float(weights @ (root * shape))
    return float(weights @ (factor * shape * nodes * nodes * root))


def moment_ratio(ratio: float, c33: float, c11: float) -> float:
    """The elliptic strips' r on the ellipse of a/b ``ratio`` (docs/physics.md, "Strips"): Kalker's spin moment
    ``G c^4 C33`` over the strips' own ``(pi/2) E_x int f(y) y^2 a(y) dy``, ``E_x = 4 G C11 / pi^2`` (f the short
    strips' stiffening), i.e. ``C33 pi / (2 C11 b^2 ... )`` in units free of the ellipse's size.  A lobe takes its
    equivalent ellipse's r: the factor by which the half-space stiffens the strips' moment of spin, applied to the
    lobe's own spread of strips."""
    gamma = ratio / (ratio + STIFFENING_SCALE)
    # G c^4 C33 / ((pi/2) (4 G C11 / pi^2) a b^3 I) with c^4 = a^2 b^2: C33 pi a / (2 C11 b I)
    return c33 * math.pi * ratio / (2.0 * c11 * _spread_shape(gamma))


class Lobes:
    """The strips in contact grouped in runs (lobes) with their equivalent ellipses' constants, as per-strip arrays
    (module docstring).  Attributes are arrays over the strips in contact (``index`` into the contact's strips) or
    lists over the lobes.  ``friction`` and ``rolling_speed`` [m/s] set the coefficient the march's flexibilities are
    taken at (:func:`~rollcontact.elliptic.methods.strips.march_flexibilities`)."""

    def __init__(self, contact: StripContact, material: Material, friction, rolling_speed: float, creepages):
        xi, eta, phi = creepages
        mu = friction.static_coefficient
        g, nu = material.youngs_modulus / (2.0 * (1.0 + material.poisson_ratio)), material.poisson_ratio
        estar = material.contact_modulus
        self.index = contact.contact.nonzero()[0]
        self.s = contact.centres[self.index]
        self.w = contact.widths[self.index]
        self.half = contact.half_lengths[self.index]
        self.q = contact.peak_pressures[self.index] / self.half
        self.m = mu * self.q
        loads = 0.5 * math.pi * contact.peak_pressures[self.index] * self.half
        starts = [0, *((self.index[1:] - self.index[:-1] > 1).nonzero()[0] + 1).tolist(), self.index.size]
        self.runs = [np.arange(a, b) for a, b in zip(starts[:-1], starts[1:], strict=True)]
        count = self.index.size
        names = ("modulus_x", "modulus_y", "modulus_phi", "factor", "centroid", "ratio", "march_ratio", "cross",
                 "l1", "l2", "l3", "limit")
        table = np.empty((len(names), count))
        self.ratios, self.clamped, self.psi_e, self.coefficients = [], [], [], []
        low, high = aspect_ratio_range()
        x0, x1, y0, y1, scale, power, spin_half, _ = SPIN_FLEXIBILITY
        for a, b in zip(starts[:-1], starts[1:], strict=True):
            part = slice(a, b)
            w, half, s = self.w[part], self.half[part], self.s[part]
            curvature = contact.longitudinal_curvature[self.index[part]]
            weighted = w * loads[part]
            stiff = float(np.sum(weighted * self.q[part] / (estar * curvature)) / np.sum(weighted))
            ratio = equivalent_ratio(stiff)
            self.clamped.append(not low <= ratio <= high)
            self.ratios.append(ratio)
            width_length = float(w @ half)
            area = 2.0 * width_length
            a_e, b_e = math.sqrt(area * ratio / math.pi), math.sqrt(area / (math.pi * ratio))
            c = extended_creepage_coefficients(ratio, nu)
            self.coefficients.append(c)
            load = float(w @ loads[part])
            p0_e = 1.5 * load / (math.pi * a_e * b_e)
            gamma = ratio / (ratio + STIFFENING_SCALE)
            shape = (half / half.max()) ** (-gamma)
            factor = shape * width_length / float(w @ (half * shape))
            centroid = float(w @ (half * s)) / width_length
            modulus_x = 4.0 * g * c.c11 / math.pi**2
            r = moment_ratio(ratio, c.c33, c.c11)
            psi_e = phi * (3.0 * g * c.c23 * math.sqrt(b_e / a_e) / math.pi) * a_e / (2.0 * mu * p0_e)
            self.psi_e.append(psi_e)
            log_ratio = math.log(ratio)
            xi_lobe = xi - phi * centroid
            flex = march_flexibilities(a_e, b_e, g, friction, rolling_speed, load, c.c11, c.c22, c.c23, xi_lobe, eta,
                                       phi, psi_e, x0 + x1 * log_ratio, y0 + y1 * log_ratio,
                                       scale * (1.0 + ratio) ** power)
            cross = 0.0 if phi != 0.0 else float(cross_coefficients(
                *(np.array([[v]]) for v in (a_e, b_e, a_e * a_e, b_e * b_e, nu, g)))[0, 0])
            table[:, part] = np.array([modulus_x, 4.0 * g * c.c22 / math.pi**2,
                                       3.0 * g * c.c23 * math.sqrt(b_e / a_e) / math.pi, 0.0, centroid, r,
                                       1.0 + (r - 1.0) / (1.0 + abs(psi_e) / spin_half), cross, *flex,
                                       mu * load])[:, None]
            table[3, part] = factor
        for name, row in zip(names, table, strict=True):
            setattr(self, name, row)
        self.xi, self.eta, self.phi = xi, eta, phi
        self.scale = self.factor / (2.0 * self.m)
        self.psi = phi * self.modulus_phi / (2.0 * self.m)
        self.offset = self.s - self.centroid
        self.longitudinal = xi - phi * self.centroid  # each lobe's longitudinal creepage about its centroid
        self.Y = eta * self.modulus_y * self.scale
        self.couple(np.zeros(count))

    def couple(self, phi_c: np.ndarray) -> None:
        """Set the scaled longitudinal slip X with the cross creepage ``phi_c`` [1/m] per strip (0 with spin)."""
        self.phi_c = phi_c
        rigid = self.longitudinal - (self.ratio * self.phi + phi_c) * self.offset
        self.X = rigid * self.modulus_x * self.scale

    def lobe_forces(self, values: np.ndarray) -> np.ndarray:
        """Each strip's lobe's sum of ``values * w`` (per strip)."""
        out = np.empty_like(values)
        for run in self.runs:
            out[run] = float(self.w[run] @ values[run])
        return out


def stick_zones(X, Y, psi, half):
    """``(d, kappa, lambda, partial, share)`` per strip (the elliptic strips' stick zones, docs/physics.md,
    "Strips"): the root d of ``(1 - psi^2) d^2 - 2 psi Y d - (X^2 + Y^2) = 0`` (the cancellation-free form where
    ``psi Y < 0``), the stick edge's traction direction ``(X/d, psi + Y/d)``, whether the strip sticks and, past
    ``|psi| = 1``, the share of its stick traction kept (``(F - v)/(F - 1)``, F = :data:`STICK_FADE`); full slip
    along ``(X, Y)``."""
    if not np.count_nonzero(psi):
        # without spin d = |(X, Y)| and the direction is (X, Y)'s, in the stick zone and in full slip
        root = np.sqrt(Y * Y + X * X)
        partial = root < half
        slipping = root > 0.0
        with np.errstate(divide="ignore", invalid="ignore"):  # where there is no slip, replaced by 0
            kappa = np.where(slipping, X / root, 0.0)
            lam = np.where(slipping, Y / root, 0.0)
        if np.count_nonzero(partial) < partial.size:  # full slip along (X, Y) / |(X, Y)| with |(X, Y)| as hypot
            norm = np.hypot(X, Y)
            with np.errstate(invalid="ignore"):
                kappa = np.where(partial, kappa, np.where(slipping, X / norm, 0.0))
                lam = np.where(partial, lam, np.where(slipping, Y / norm, 0.0))
        return np.where(partial, root, half), kappa, lam, partial, np.ones_like(X)
    turned = psi * Y
    room = 1.0 - psi * psi
    square = Y * Y + room * X * X
    real = square >= 0.0
    root = np.sqrt(np.where(real, square, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        alike = (turned + root) / np.where(room > 0.0, room, 1.0)
        opposed = (X * X + Y * Y) / (root - turned)
    d = np.where(turned < 0.0, np.where(real, opposed, np.inf), np.where(room > 0.0, alike, np.inf))
    partial = d < half
    edge = partial & (d > 0.0)
    safe = np.where(edge, d, 1.0)
    kappa = np.where(edge, X / safe, 0.0)
    lam = np.where(edge, psi + Y / safe, 0.0)
    share = np.ones_like(X)
    if np.count_nonzero(np.abs(psi) >= 1.0) and np.count_nonzero(partial):
        along = 1.0 - lam * psi
        rest = np.sqrt(np.where(partial, (half - d) / half, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            excess = np.where(room > 0.0, 0.0, np.where(along > 0.0, rest * (2.0 * along - room) / (2.0 * along),
                                                        np.inf))
        partial &= excess < STICK_FADE
        share = np.minimum(np.maximum((STICK_FADE - excess) / (STICK_FADE - 1.0), 0.0), 1.0)
    norm = np.hypot(X, Y)
    slipping = norm > 0.0
    safe_norm = np.where(slipping, norm, 1.0)
    kappa = np.where(partial, kappa, np.where(slipping, X / safe_norm, 0.0))
    lam = np.where(partial, lam, np.where(slipping, Y / safe_norm, 0.0))
    return np.where(partial, d, half), kappa, lam, partial, share


def closed_form(lobes: Lobes, stick) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per strip and unit width ``(Fx, Fy, Mz)`` [N/m, N/m, N]: ``(pi m/2) kappa (a^2 - a*^2)``,
    ``(pi m/2) (lambda a^2 - (lambda - psi) a*^2)``, ``-(pi m/2)(lambda - psi) d a*^2 - s Fx`` (the elliptic
    strips' closed form with ``m = mu q_j``; Mz about the rigid contact point)."""
    d, kappa, lam, partial, _ = stick
    rest2 = np.where(partial, lobes.half - d, 0.0) ** 2
    turned = lam - lobes.psi
    area = 0.5 * math.pi * lobes.m
    fx = area * kappa * (lobes.half**2 - rest2)
    fy = area * (lam * lobes.half**2 - turned * rest2)
    return fx, fy, -area * turned * d * rest2 - lobes.s * fx


def coulomb_forces(lobes: Lobes, steps: int, fields: bool):
    """``((Fx, Fy, Mz), field)`` [N, N, N m] of Coulomb friction: the closed form with the cross influence's fixed
    point (without spin), plus the march's departure with spin; the field on the cells with ``fields``."""
    stick = stick_zones(lobes.X, lobes.Y, lobes.psi, lobes.half)
    spin = lobes.phi != 0.0
    if not spin and np.count_nonzero(lobes.cross):
        for _ in range(CROSS_ITERATIONS):
            fy = lobes.lobe_forces(closed_form(lobes, stick)[1])
            lobes.couple(lobes.cross * fy)
            stick = stick_zones(lobes.X, lobes.Y, lobes.psi, lobes.half)
    per_strip = closed_form(lobes, stick)
    forces = np.array([float(lobes.w @ f) for f in per_strip])
    field = None
    if spin or fields:
        departure, field = marched(lobes, steps, stick, fields)
        if spin:
            forces = forces + departure
    return forces, field


def marched(lobes: Lobes, steps: int, stick, fields: bool):
    """The strips on ``steps`` cells each: the stick zones' closed-form traction, ``mu p`` along a FASTSIM march's
    traction in the slip zones (the elliptic strips' march, docs/physics.md, "Strips", with each strip's own bound
    ``mu q_j sqrt(a_j^2 - x^2)``, scaled on the cells to carry the strip's ``mu`` times its load).  Returns the
    march's departure from the closed form ``(dFx, dFy, dMz)`` and, with ``fields``, the traction field."""
    d, kappa, lam, partial, share = stick
    half, s, w = lobes.half, lobes.s, lobes.w
    dx = 2.0 * half / steps
    x = half * cells(steps)  # (steps, strips): cell centres from the leading edge
    full = np.sqrt(np.maximum(half * half - x * x, 0.0))
    bound = lobes.m * full
    scaling = (0.5 * math.pi * lobes.m * half * half) / np.maximum(np.sum(bound, axis=0) * dx, TINY)
    bound *= scaling
    phi_x = lobes.march_ratio * lobes.phi + lobes.phi_c
    increment = np.empty((steps, 2, s.size))
    increment[:, 0] = dx * (lobes.longitudinal - phi_x * lobes.offset) / lobes.l1 * lobes.factor
    increment[:, 1] = dx * (lobes.eta / lobes.l2 + lobes.phi * (x - 0.5 * dx) / lobes.l3)
    trial = np.empty((steps, 2, s.size))
    trial[0, 0] = 0.5 * increment[0, 0]
    trial[0, 1] = 0.5 * dx * (lobes.eta / lobes.l2 + lobes.phi * (half - 0.25 * dx) / lobes.l3)
    size = np.empty(s.size)
    ratio = np.empty(s.size)
    with np.errstate(over="ignore"):
        for i in range(steps - 1):
            np.hypot(trial[i, 0], trial[i, 1], out=size)
            np.maximum(size, TINY, out=size)
            np.divide(bound[i], size, out=ratio)
            np.minimum(ratio, 1.0, out=ratio)
            np.multiply(trial[i], ratio, out=trial[i + 1])
            trial[i + 1] += increment[i]
    size = np.maximum(np.hypot(trial[:, 0], trial[:, 1]), TINY)
    qx, qy = bound * trial[:, 0] / size, bound * trial[:, 1] / size
    if lobes.phi == 0.0:  # without spin the slip direction is uniform along the strip
        qx, qy = bound * kappa, bound * lam
    ux, uy = bound * kappa, bound * lam
    in_stick = partial & (x > 2.0 * d - half)
    if np.count_nonzero(partial):
        rest = half - d
        inner = np.sqrt(np.maximum(rest * rest - (x - d) ** 2, 0.0))
        m = lobes.m * scaling
        stick_x, stick_y = m * kappa * (full - inner), m * (lam * full - (lam - lobes.psi) * inner)
        ux, uy = np.where(in_stick, stick_x, ux), np.where(in_stick, stick_y, uy)
        if np.count_nonzero(share < 1.0):
            within = np.minimum(1.0, bound / np.maximum(np.hypot(stick_x, stick_y), TINY))
            stick_x = np.where(share < 1.0, share * within * stick_x + (1.0 - share) * qx, stick_x)
            stick_y = np.where(share < 1.0, share * within * stick_y + (1.0 - share) * qy, stick_y)
        qx, qy = np.where(in_stick, stick_x, qx), np.where(in_stick, stick_y, qy)
    weight = w * dx
    dqx, dqy = qx - ux, qy - uy
    departure = np.array([float(np.sum(dqx * weight)), float(np.sum(dqy * weight)),
                          float(np.sum((x * dqy - s * dqx) * weight))])
    if not fields:
        return departure, None
    pressure = bound * (lobes.q / lobes.m)
    field = TractionField(*(v.T.copy() for v in (x, np.broadcast_to(s, x.shape), pressure, qx, qy, in_stick)))
    return departure, field


def falling_march_forces(lobes: Lobes, friction, speed: float, steps: int, fields: bool):
    """``((Fx, Fy, Mz), field, steepness)`` of velocity-dependent friction, with or without spin: the elliptic strips'
    falling-friction path (docs/physics.md, "Strips") on the patch's strips, the stick zones and the closed form (with
    the cross influence's fixed point, without spin) at the static coefficient, the march's cells at the coefficient of
    their own slip (:func:`falling_marched`); ``lobes`` built with the static coefficient."""
    stick = stick_zones(lobes.X, lobes.Y, lobes.psi, lobes.half)
    if lobes.phi == 0.0 and (lobes.cross != 0.0).any():
        for _ in range(CROSS_ITERATIONS):
            fy = lobes.lobe_forces(closed_form(lobes, stick)[1])
            lobes.couple(lobes.cross * fy)
            stick = stick_zones(lobes.X, lobes.Y, lobes.psi, lobes.half)
    forces = np.array([float(lobes.w @ f) for f in closed_form(lobes, stick)])
    departure, field, steepness = falling_marched(lobes, steps, stick, friction, speed, fields)
    return forces + departure, field, steepness


def falling_marched(lobes: Lobes, steps: int, stick, friction, speed: float, fields: bool):
    """The falling-friction march on the patch's strips (:func:`marched`'s cells and increments, each cell's bound
    ``mu(V sigma) p`` at its own slip over :data:`~rollcontact.elliptic.methods.strips.FALLING_PASSES` marches with
    spin, one without, each cell's slip in its strip's half-plane:
    :func:`~rollcontact.elliptic.methods.strips.elastic_slips`).  Returns the departure from the closed form ``(dFx,
    dFy, dMz)``, the field (with ``fields``) and the steepness."""
    d, kappa, lam, partial, share = stick
    half, s, w = lobes.half, lobes.s, lobes.w
    dx = 2.0 * half / steps
    x = half * cells(steps)
    full = np.sqrt(np.maximum(half * half - x * x, 0.0))
    bound = lobes.m * full
    scaling = (0.5 * math.pi * lobes.m * half * half) / np.maximum(np.sum(bound, axis=0) * dx, TINY)
    bound *= scaling
    static = friction.static_coefficient
    pressure = bound / static
    phi_x = lobes.march_ratio * lobes.phi + lobes.phi_c
    increment = np.empty((steps, 2, s.size))
    increment[:, 0] = dx * (lobes.longitudinal - phi_x * lobes.offset) / lobes.l1 * lobes.factor
    increment[:, 1] = dx * (lobes.eta / lobes.l2 + lobes.phi * (x - 0.5 * dx) / lobes.l3)
    first = np.array([0.5 * increment[0, 0], 0.5 * dx * (lobes.eta / lobes.l2 + lobes.phi * (half - 0.25 * dx)
                                                          / lobes.l3)])
    flexibility = (lobes.l1 / (lobes.factor * dx), lobes.l2 / dx)
    kernel = friction_kernel(friction)
    coefficient = np.full(bound.shape, static)
    ux, uy = bound * kappa, bound * lam  # the closed form's traction
    in_stick = partial & (x > 2.0 * d - half)
    m = lobes.m * scaling  # the cells' scale of mu p
    if partial.any():
        inner = np.sqrt(np.maximum((half - d) ** 2 - (x - d) ** 2, 0.0))
        stick_x, stick_y = m * kappa * (full - inner), m * (lam * full - (lam - lobes.psi) * inner)
        ux, uy = np.where(in_stick, stick_x, ux), np.where(in_stick, stick_y, uy)
    compliance = (1.0 / (lobes.factor * lobes.modulus_x), 1.0 / (lobes.factor * lobes.modulus_y))
    sigma = growth = None
    for _ in range(FALLING_PASSES if lobes.phi != 0.0 else 1):
        marched = march(first, increment, coefficient * pressure)
        *_, rigid = march_slips(marched, first, increment, flexibility)
        if growth is None:  # the elastic slip per unit coefficient, from the first march's (at mu(0)) half-plane slip
            departure = None
            if lobes.phi != 0.0:  # the march's traction turns away from the closed form's
                trial, _, size = marched
                departure = np.where(in_stick, 0.0, bound * trial.transpose(1, 0, 2) / size - (ux, uy))
            slip = elastic_slips(x, half, d, kappa, lam, lobes.psi, lobes.X, lobes.Y, partial, in_stick, m,
                                 compliance, departure)
            growth = (rigid - slip) / static
        sigma, coefficient, steepness = slips_at(rigid, growth, ~in_stick & (rigid > growth * static), friction,
                                                 kernel, speed, sigma)
    limit = coefficient * pressure
    if lobes.phi != 0.0:
        trial, _, size = marched
        qx, qy = limit * trial[:, 0] / size, limit * trial[:, 1] / size
    else:  # without spin the slip direction is uniform along the strip
        qx, qy = limit * kappa, limit * lam
    if partial.any():
        if (share < 1.0).any():
            within = np.minimum(1.0, bound / np.maximum(np.hypot(stick_x, stick_y), TINY))
            stick_x = np.where(share < 1.0, share * within * stick_x + (1.0 - share) * qx, stick_x)
            stick_y = np.where(share < 1.0, share * within * stick_y + (1.0 - share) * qy, stick_y)
        qx, qy = np.where(in_stick, stick_x, qx), np.where(in_stick, stick_y, qy)
    weight = w * dx
    dqx, dqy = qx - ux, qy - uy
    departure = np.array([float(np.sum(dqx * weight)), float(np.sum(dqy * weight)),
                          float(np.sum((x * dqy - s * dqx) * weight))])
    field = None
    if fields:
        field = TractionField(*(np.broadcast_to(v, x.shape).T.copy() for v in (x, s, pressure, qx, qy, in_stick)))
    return departure, field, float(steepness.max())
