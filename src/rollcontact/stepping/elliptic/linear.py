"""Kalker's linear theory for every contact of an elliptic stepping model at once: :class:`LinearContacts`."""

from __future__ import annotations

import math

from rollcontact.elliptic.creep_coefficients import creepage_coefficients
from rollcontact.elliptic.hertz import differences, eccentricity
from rollcontact.stepping.elliptic.parameters import LEVEL_CODES, NO_STICK, ZERO, EllipticOutputs
from rollcontact.stepping.parameters import new_tuple


class LinearContacts:
    """Kalker's linear theory for every contact of a model, without a solver call per contact.

    What depends on the curvatures alone (Hertz's eccentricity and elliptic integrals, the orientation, Kalker's
    coefficients at a/b) is taken once from the library's own functions; each step evaluates, per contact, the
    expressions of :func:`rollcontact.elliptic.hertz_ellipse` (``alpha^3 = 3 Fn (K - E)/e^2 / (2 pi E* A_major)``,
    ``beta = g alpha``, ``p0 = A_major E* alpha / (g (K - E)/e^2)``), of the linear level
    (:func:`rollcontact.elliptic.methods.common.linear_forces`) and of :meth:`EllipticModel.linear_slopes`, operation
    for operation, so that the outputs equal the single-contact path's bit for bit.  The evaluation is a loop of
    float arithmetic over the contacts: a vehicle's few contacts cost less so than numpy's fixed cost per array
    operation (some 40 of them per step), and the C library's ``pow`` and ``sqrt`` are the ones ``hertz_ellipse``
    calls (numpy's vectorised power may differ in the last bit).
    """

    def __init__(self, model):
        self.contact_modulus = model.material.contact_modulus
        self.poisson_ratio = model.material.poisson_ratio
        self.constants = [self.contact_constants(A, B) for A, B in model.curvatures]
        self.shear_modulus = model.material.shear_modulus

    def contact_constants(self, A: float, B: float) -> tuple:
        """What a contact's steps take from its curvatures A, B [1/m] alone (:func:`contact_constants`)."""
        return contact_constants(A, B, self.contact_modulus, self.poisson_ratio)

    def use_curvatures(self, changed, curvatures) -> None:
        """Take the curvatures ``(A, B)`` of the contacts ``changed`` (indices) from ``curvatures``."""
        for k in changed:
            self.constants[k] = self.contact_constants(*curvatures[k])

    def step(self, rows, contacts=None) -> tuple[EllipticOutputs, ...]:
        """The outputs of every contact for its checked inputs (rows of floats as :meth:`EllipticModel.step`'s), or of
        the ``contacts`` (indices) whose rows ``rows`` are.  A contact without load is :data:`ZERO`."""
        shear = self.shear_modulus
        code = LEVEL_CODES["linear"]
        outputs = []
        every = self.constants if contacts is None else [self.constants[k] for k in contacts]
        for (fn, xi, eta, phi, velocity), constants in zip(rows, every, strict=True):
            if fn == 0.0:
                outputs.append(ZERO)
                continue
            major, denominator, g, pressure_scale, g_major, along_x, c11, c22, c23, c33 = constants
            alpha = (3.0 * fn * major / denominator) ** (1.0 / 3.0)
            beta = g * alpha
            p0 = pressure_scale * alpha / g_major
            a, b = (alpha, beta) if along_x else (beta, alpha)
            length = math.sqrt(a * b)
            area = length * length
            fx = shear * area * c11 * xi
            fy = shear * area * (c22 * eta + length * c23 * phi)
            mz = shear * area * length * (-c23 * eta + (length * c33 * phi if phi != 0.0 else 0.0))
            slope = shear * length * length
            lever = slope * length
            cross = lever * c23
            power = velocity * (xi * fx + eta * fy + phi * mz)
            outputs.append(new_tuple(EllipticOutputs, (fx, fy, mz, a, b, p0, NO_STICK, power, slope * c11, 0.0, 0.0,
                                                       0.0, slope * c22, cross, 0.0, -cross, lever * length * c33,
                                                       code)))
        return tuple(outputs)


def contact_constants(A: float, B: float, contact_modulus: float, poisson_ratio: float) -> tuple:
    """What a contact's steps take from its curvatures A, B [1/m] alone, with E* [Pa] and nu: ``(K - E)/e^2`` of the
    major axis, ``2 pi E* A_major``, ``g = beta/alpha``, ``A_major E*``, ``g (K - E)/e^2``, whether the major axis lies
    along x, and Kalker's C11, C22, C23, C33 at a/b (:class:`LinearContacts`)."""
    major_curvature, minor_curvature = (A, B) if A <= B else (B, A)
    m = eccentricity(minor_curvature / major_curvature)
    major, _, _ = differences(m)
    g = math.sqrt(1.0 - m)
    c = creepage_coefficients(g if A > B else 1.0 / g, poisson_ratio)
    return (major, 2.0 * math.pi * contact_modulus * major_curvature, g, major_curvature * contact_modulus,
            g * major, A <= B, c.c11, c.c22, c.c23, c.c33)
