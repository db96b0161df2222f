"""What the elliptic batch tests compare bit for bit: everything an :class:`~rollcontact.EllipticResult` holds."""

from __future__ import annotations

import numpy as np


def outcome(result):
    """Everything a result holds, the traction fields' arrays included, for comparisons bit for bit."""
    fields = None if result.fields is None else tuple(
        np.asarray(getattr(result.fields, name)).tobytes() for name in ("x", "y", "pressure", "traction_x",
                                                                        "traction_y", "stick"))
    return (result.method, result.success, result.message, result.longitudinal_force, result.lateral_force,
            result.spin_moment, result.a, result.b, result.max_pressure, result.approach,
            tuple(sorted((k, repr(v)) for k, v in result.info.items())), fields)
