"""The undeformed gap of one contact patch in its tangent plane: what the contact geometry hands the normal and
tangential methods (:class:`PatchGap`).

Each patch is solved as a planar contact in the tangent plane at its rigid contact point (the point of least
separation of the profiles): x along the track (the rolling direction, the wheel rolls towards +x), s across the
patch in the tangent plane (along the profiles' tangent at the contact point, increasing with the track's y), n the
common normal.  The undeformed separation of the surfaces along n is

    g(x, s) = lateral_gap(s) + longitudinal_curvature(s) x^2,

``lateral_gap`` from the two profiles at x = 0 (0 at the rigid contact point, >= 0 elsewhere up to the sampling),
``longitudinal_curvature`` the sum of the two surfaces' normal curvatures along x over 2 (the wheel's
``cos(delta(s)) / (2 r(s))`` at the profile point of rolling radius r and local contact angle delta; 0 for a straight
rail).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PatchGap:
    """The undeformed gap of one patch in its tangent plane (SI units; module docstring).

    Attributes
    ----------
    lateral : ndarray
        s [m], strictly increasing, where the gap is sampled across the patch region (the tangent plane's lateral
        coordinate, 0 at the rigid contact point).
    lateral_gap : ndarray
        h(s) [m] >= 0, the separation along the normal at x = 0.
    longitudinal_curvature : ndarray
        A(s) [1/m] > 0: the gap grows as A(s) x^2 along the rolling direction.
    """

    lateral: np.ndarray
    lateral_gap: np.ndarray
    longitudinal_curvature: np.ndarray
