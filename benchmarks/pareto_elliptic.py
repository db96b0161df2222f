"""The elliptic (3D) family of the Pareto study: every elliptic level and setting on a few wheel/rail contacts, and
``solve_elliptic``'s choice at each requested tolerance (``pareto.py`` runs it and reports it with the 2D families).

Cases: a/b 0.2, 1 and 5 with combined longitudinal and lateral creepage and large spin, and a/b 1 with longitudinal
creepage alone, in units of the creepage whose linear force is mu Fn (:func:`elliptic_cases`).  Error: the largest of
``|dFx|/(mu Fn)``, ``|dFy|/(mu Fn)`` and ``|dMz|/(mu Fn c)`` (the contract of ``solve_elliptic(scene,
tolerance=t)``) against the discretised 3D level's Richardson pair 120/60 (``REFERENCE``); the pressure is Hertz's on
every level (error 0).  Time: median per ``solve_elliptic`` call.  The rows' methods carry the prefix ``3D`` so that
the 2D cost-model fits leave them out.
"""

from __future__ import annotations

import math

import common
from pareto_cases import AutoChoice, Row, setting_label

import rollcontact as rc
from rollcontact.elliptic.dispatch import METHODS as ELLIPTIC_METHODS
from rollcontact.elliptic.dispatch import solve as solve_elliptic

FAMILY = "elliptic (3D)"
MU, LOAD, SIZE = 0.3, 1e5, 6e-3  # Coulomb coefficient, Fn [N], c = sqrt(ab) [m]
MATERIAL = rc.Material(210e9, 0.28)
REFERENCE = {"elements": 120, "extrapolate": True}
SETTINGS = (("linear", {}), ("fastsim", {"nx": 20, "ny": 20}), ("fastsim", {"nx": 40, "ny": 40}),
            ("fastsim", {"nx": 100, "ny": 100}), ("strips", {}),
            ("discretised", {"elements": 16, "extrapolate": False}),
            ("discretised", {"elements": 32, "extrapolate": False}),
            ("discretised", {"elements": 60, "extrapolate": False}),
            ("discretised", {"elements": 32, "extrapolate": True}),
            ("discretised", {"elements": 60, "extrapolate": True}))
TOLERANCES = (0.1, 0.03, 0.01)


def elliptic_cases(quick: bool) -> list[tuple[str, rc.EllipticScene]]:
    """``(label, scene)``: (a/b, xi, eta, psi) with the creepages in units of the creepage whose linear force is
    mu Fn and the spin in units of the spin whose linear lateral force is mu Fn."""
    specs = ((1.0, 0.5, 0.5, 1.0),) if quick else ((0.2, 0.5, 0.5, 2.0), (1.0, 0.5, 0.5, 1.0), (5.0, 0.5, 0.5, 2.0),
                                                   (1.0, 1.0, 0.0, 0.0))
    out = []
    for ratio, xi, eta, psi in specs:
        base = rc.EllipticScene.from_semi_axes(LOAD, SIZE * math.sqrt(ratio), SIZE / math.sqrt(ratio),
                                               material=MATERIAL, friction=MU)
        k = rc.creepage_coefficients(ratio, MATERIAL.poisson_ratio)
        unit = MU * LOAD / (base.shear_modulus * SIZE * SIZE)
        scene = base.replace(longitudinal_creepage=xi * unit / k.c11, lateral_creepage=eta * unit / k.c22,
                             spin_creepage=psi * unit / (k.c23 * SIZE))
        out.append((f"a/b {ratio:g}, xi {xi:g}, eta {eta:g}, spin {psi:g}", scene))
    return out


def error_of(result, reference) -> float:
    """The largest error of Fx, Fy over mu Fn and Mz over mu Fn c."""
    return max(abs(a - b) for a, b in zip(result.force_coefficients, reference.force_coefficients, strict=True))


def elliptic_study(quick: bool) -> tuple[list[Row], list[AutoChoice], list[tuple[str, str]]]:
    """Rows of every setting, auto's choices and the references (case, how) of the elliptic family."""
    rows, choices, references = [], [], []
    for case, scene in elliptic_cases(quick):
        reference = solve_elliptic(scene, "discretised", **REFERENCE)
        references.append((case, "discretised 3D, Richardson pair 120/60"))
        case_rows = []
        for method, options in SETTINGS:
            spec = ELLIPTIC_METHODS[method]
            result = solve_elliptic(scene, method, **options)
            seconds = common.median_time(lambda s=scene, m=method, o=options: solve_elliptic(s, m, **o),
                                         min_repeats=3, min_seconds=0.2 if method != "discretised" else 0.0)
            case_rows.append(Row(FAMILY, case, f"3D {method}", setting_label(method, options), options,
                                 error_of(result, reference), 0.0, seconds, spec.accuracy.cost(scene, options),
                                 spec.accuracy.error(scene, options)))
        for t in TOLERANCES:
            result = solve_elliptic(scene, tolerance=t)
            seconds = common.median_time(lambda s=scene, t=t: solve_elliptic(s, tolerance=t), min_repeats=3,
                                         min_seconds=0.2)
            label = setting_label(result.method, result.info.get("setting", {}))
            error = error_of(result, reference)
            for r in case_rows:
                if r.label == label:
                    r.auto += (t,)
            meeting = [r for r in case_rows if r.error <= t]
            certified = [r for r in case_rows if r.bound <= t]
            cheapest = min(meeting, key=lambda r: r.time) if meeting else None
            safest = min(certified, key=lambda r: r.time) if certified else None
            choices.append(AutoChoice(FAMILY, case, t, f"3D {result.method}", label, error, seconds,
                                      result.info.get("error_estimate", math.nan), error <= t,
                                      cheapest.label if cheapest else "", cheapest.time if cheapest else math.nan,
                                      certified=safest.label if safest else "",
                                      certified_time=safest.time if safest else math.nan))
        rows += case_rows
    return rows, choices, references
