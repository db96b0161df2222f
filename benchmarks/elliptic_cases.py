"""The elliptic case sets the elliptic studies share (``calibrate_elliptic_levels.py``, ``calibrate_strips_spin.py``):
the contact (Coulomb friction mu 0.3, Fn 100 kN, c = sqrt(ab) = 6 mm, G 82 GPa, nu 0.28) at a/b 0.2 ... 5 and creepages
in units of the creepage whose linear force is 3 mu Fn.  Not a study: nothing to run."""

import math

import rollcontact as rc

MU, LOAD, C = 0.3, 1e5, 6e-3  # Coulomb coefficient, Fn [N], c = sqrt(ab) [m]
MATERIAL = rc.Material(2 * 82e9 * 1.28, 0.28)  # G = 82 GPa, nu = 0.28
FACTORS = (0.05, 0.3, 1.0, 3.0)
SPIN_FACTORS = (0.4, 0.6, 1.5, 2.0, 5.0)


def saturation(ratio: float, friction=MU, poisson_ratio: float = MATERIAL.poisson_ratio):
    """The contact at a/b = ``ratio`` without creepage (G 82 GPa and nu = ``poisson_ratio``), and the creepages xi, eta
    [1] and spin [1/m] whose linear force (moment arm c for spin) is 3 mu Fn: the unit of the case sets."""
    material = rc.Material(2 * 82e9 * (1 + poisson_ratio), poisson_ratio)
    base = rc.EllipticScene.from_semi_axes(LOAD, C * math.sqrt(ratio), C / math.sqrt(ratio), material=material,
                                           friction=friction)
    k = rc.creepage_coefficients(ratio, poisson_ratio)
    g = base.shear_modulus
    return base, (3 * MU * LOAD / (g * C * C * k.c11), 3 * MU * LOAD / (g * C * C * k.c22),
                  3 * MU * LOAD / (g * C**3 * k.c23))


def cases(ratios=(0.2, 0.5, 1.0, 2.0, 5.0), friction=MU, poisson_ratio: float = MATERIAL.poisson_ratio):
    """``(group, scene)`` pairs at a/b = ``ratios``: pure creepages at FACTORS and spin alone or with half of xi or
    eta (or 0.3 xi and -0.5 eta) at the last three of FACTORS and at SPIN_FACTORS, in units of the creepage whose
    linear force is 3 mu Fn."""
    out = []
    for ratio in ratios:
        base, (xi_s, eta_s, phi_s) = saturation(ratio, friction, poisson_ratio)
        for f in FACTORS:
            out += [("no spin", base.replace(longitudinal_creepage=f * xi_s)),
                    ("no spin", base.replace(lateral_creepage=f * eta_s)),
                    ("spin", base.replace(spin_creepage=f * phi_s))]
        for f in FACTORS[1:] + SPIN_FACTORS:
            if f in SPIN_FACTORS:
                out.append(("spin", base.replace(spin_creepage=f * phi_s)))
            out += [("spin", base.replace(longitudinal_creepage=0.5 * f * xi_s, spin_creepage=f * phi_s)),
                    ("spin", base.replace(lateral_creepage=0.5 * f * eta_s, spin_creepage=f * phi_s)),
                    ("spin", base.replace(longitudinal_creepage=0.3 * f * xi_s, lateral_creepage=-0.5 * f * eta_s,
                                          spin_creepage=f * phi_s))]
    return out


def operating_points(ratios=(0.2, 0.5, 1.0, 2.0, 5.0), poisson_ratio: float = MATERIAL.poisson_ratio) -> list:
    """Small creepages with small spin, as a wheel on a rail meets them: xi 0.05 and 0.15, eta half that, spin 0.05,
    0.15 and 0.3, in the units of :func:`cases`."""
    out = []
    for ratio in ratios:
        base, (xi_s, eta_s, phi_s) = saturation(ratio, poisson_ratio=poisson_ratio)
        out += [base.replace(longitudinal_creepage=f * xi_s, lateral_creepage=0.5 * f * eta_s,
                             spin_creepage=s * phi_s) for f in (0.05, 0.15) for s in (0.05, 0.15, 0.3)]
    return out


OPPOSED = ((0.0, -0.5), (0.3, -0.5), (0.0, -1.0), (0.5, -0.25))
"""(xi, eta) per unit of spin, in saturations, of :func:`opposed_lines`: lateral creepage against the spin."""


def opposed_lines(ratios=(0.2, 0.5, 1.0, 2.0, 5.0), spins=tuple(k / 10 for k in range(5, 26))) -> list:
    """``(line, scene)`` pairs: spin of ``f`` saturations (``spins``: 0.5 .. 2.5, through the strips' ``|psi| = 1`` at
    f = 1) with the creepages ``OPPOSED`` times f, a saturation being a third of the unit of :func:`cases`; ``line``
    names a/b and the direction, the scenes of a line in the order of ``spins``."""
    out = []
    for ratio in ratios:
        base, (xi_s, eta_s, phi_s) = saturation(ratio)
        for cx, ce in OPPOSED:
            out += [(f"a/b {ratio:g}, (xi, eta) = ({cx:g}, {ce:g}) phi",
                     base.replace(longitudinal_creepage=cx * f * xi_s / 3, lateral_creepage=ce * f * eta_s / 3,
                                  spin_creepage=f * phi_s / 3)) for f in spins]
    return out


SWEEP = (0.75, 1.25, 1.5, 1.75, 2.25, 2.5, 2.75, 3.5, 4.0)
"""Spins of :func:`spin_sweep`, in saturations (apart from the levels 1, 2 and 3 of ``bench_elliptic.py``'s matrix)."""


def spin_sweep(ratios=(0.2, 0.5, 1.0, 2.0, 5.0)) -> list:
    """Spin alone at ``SWEEP`` saturations (a third of the unit of :func:`cases`), through the strips' full slip at
    ``|psi| = 1`` and beyond, where the strips' moment at a/b = 5 is least accurate."""
    out = []
    for ratio in ratios:
        base, (_, _, phi_s) = saturation(ratio)
        out += [base.replace(spin_creepage=f * phi_s / 3) for f in SWEEP]
    return out
