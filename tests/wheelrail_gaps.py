"""Synthetic patch gaps for the wheel/rail patch tests: a quadratic gap (Hertz's), two separate wells (a two-lobed
patch), a longitudinal curvature that varies strongly across the patch, a well beside a shelf (a flange root's), and
their mirror images."""

from __future__ import annotations

import numpy as np

from rollcontact import EllipticScene, Material
from rollcontact.elliptic.hertz import hertz_ellipse
from rollcontact.wheelrail.patch import PatchGap

LOAD = 1e5
MU = 0.3


def quadratic(ratio: float = 1.0, c: float = 6e-3, load: float = LOAD, samples: int = 1201, span: float = 3.0):
    """``(PatchGap, EllipticScene)`` of the gap ``A x^2 + B s^2`` whose Hertz ellipse under ``load`` has
    ``a/b = ratio`` and ``sqrt(ab) = c``; s sampled over ``+-span b``."""
    a, b = c * ratio**0.5, c / ratio**0.5
    scene = EllipticScene.from_semi_axes(load, a, b, friction=MU)
    s = np.linspace(-span * b, span * b, samples)
    return PatchGap(s, scene.lateral_curvature * s * s, np.full(s.size, scene.longitudinal_curvature)), scene


def two_wells(separation: float = 8e-3, depth: float = 6e-6, curvature: float = 4.0, longitudinal: float = 1.1,
              samples: int = 1601) -> PatchGap:
    """Two parabolic wells ``B (s - s_k)^2`` (B = ``curvature`` [1/m]) at ``s = 0`` and ``s = separation``, the second
    ``depth`` [m] shallower, their crossing the ridge between them: two separate interpenetration intervals at
    moderate approaches."""
    s = np.linspace(-separation, 2.0 * separation, samples)
    h = np.minimum(curvature * s * s, curvature * (s - separation) ** 2 + depth)
    return PatchGap(s, h, np.full(s.size, longitudinal))


def three_wells(separation: float = 8e-3, depth: float = 4e-6, curvature: float = 4.0, longitudinal: float = 1.1,
                samples: int = 2401) -> PatchGap:
    """Three parabolic wells as :func:`two_wells`', each ``depth`` [m] shallower than the one before: three lobes."""
    s = np.linspace(-separation, 3.0 * separation, samples)
    h = np.min([curvature * (s - k * separation) ** 2 + k * depth for k in range(3)], axis=0)
    return PatchGap(s, h, np.full(s.size, longitudinal))


def varying_curvature(slope: float = 60.0, lateral: float = 3.0, longitudinal: float = 1.1,
                      samples: int = 1201) -> PatchGap:
    """``h = B s^2 + C s^3`` (a flange root's lopsided gap) with ``A(s) = A0 (1 + slope s)`` held above A0 / 4: the
    curvature along x changes by half across a 10 mm patch."""
    s = np.linspace(-15e-3, 15e-3, samples)
    h = lateral * s * s + 60.0 * np.abs(s) ** 3
    return PatchGap(s, h, longitudinal * np.maximum(1.0 + slope * s, 0.25))


def shelf(height: float = 0.95, lateral: float = 24.0, longitudinal: float = 1.0, reach: float = 10e-3,
          rise: float = 2.0, load: float = 8e4, samples: int = 1201) -> PatchGap:
    """A well ``B s^2`` (B = ``lateral`` [1/m]) that flattens on one side into a shelf ``height`` times Hertz's
    approach under ``load`` [N] above its bottom, ``d (1 - exp(-B s^2 / d))``, rising again ``rise (s - reach)^2``
    beyond ``reach`` [m] (S1002's flange root on UIC60 under a heavy wheel): at Hertz's approach the rigid
    interpenetration spans the shelf, the contact stays in the well (height near 1) or takes a second lobe on the
    shelf's far end (lower shelves)."""
    depth = height * hertz_ellipse(load, longitudinal, lateral, Material().contact_modulus).approach
    s = np.linspace(-15e-3, 25e-3, samples)
    h = np.where(s < 0.0, lateral * s * s, depth * -np.expm1(-lateral * s * s / depth)
                 + rise * np.maximum(s - reach, 0.0) ** 2)
    return PatchGap(s, h, np.full(s.size, longitudinal))


def mirrored(gap: PatchGap) -> PatchGap:
    """``h(-s)``, ``A(-s)``."""
    return PatchGap(-np.asarray(gap.lateral)[::-1], np.asarray(gap.lateral_gap)[::-1],
                    np.asarray(gap.longitudinal_curvature)[::-1])
