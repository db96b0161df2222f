"""The Pareto study's cases: configuration, steady scene families, settings, references and the records of a run.

The method: the docstring of ``benchmarks/pareto.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from instationary_case import ESTAR

import rollcontact as rc
from rollcontact.line.hertz import hertz
from rollcontact.line.methods.discretised.accuracy import DiscretisedAccuracy
from rollcontact.line.methods.discretised.steady import DISCRETISED_ELEMENTS
from rollcontact.line.methods.polynomial.accuracy import SLIP_NODES, TRUNCATIONS

TOLERANCES = (1e-2, 1e-3, 1e-4)  # the tolerances requested of auto
NOT_STEADY_2D = ("instationary", "elliptic (3D)")  # families outside the 2D steady analyses and cost-model fits
LOAD = 1e6  # N' [N/m] of the steady cases
A_HERTZ = hertz(LOAD, 0.46, ESTAR)[0]
SATURATION = 0.3 * A_HERTZ / 0.46  # Carter's saturation creep mu a / R


# ------------------------------------------------------------------------------------------------ configuration
@dataclass(frozen=True)
class Config:
    """What a run measures: the full study or the quick smoke test."""

    quick: bool
    budget: float  # s of timing per setting
    poly_orders: tuple[int, ...]
    poly_tolerances: tuple[float, ...]
    nodes: tuple[int, ...]
    elements: tuple[int, ...]
    structured_elements: tuple[int, ...]
    reference_nodes: int
    richardson: tuple[int, int] | None
    split_reference: tuple[int, int]
    extrapolated_elements: tuple[int, ...]  # coarser levels n of the extrapolated discretised pairs (constant mu)
    signals: tuple[tuple[float, float, float], ...]  # instationary (lambda / a, mean, amplitude): creep_signal
    transient_elements: tuple[int, ...]
    transient_pairs: tuple[int, ...]  # finer grid's elements of the extrapolating pairs
    transient_reference: int  # the pair n/2, n of the reference
    fmu_rounds: int


FULL = Config(False, 0.3, (1, 2, 4, 8, 16, 32), TRUNCATIONS, SLIP_NODES,
              DISCRETISED_ELEMENTS, (50, 100, 200, 400, 800), 1024, (800, 1600), (2000, 4000),
              (50, 100, 200, 400, 800),
              ((5.0, 0.5, 0.3), (10.0, 0.5, 0.3), (20.0, 0.5, 0.3), (40.0, 0.5, 0.3), (5.0, 0.0, 0.9),
               (10.0, 0.5, 0.1)),
              (50, 100, 200, 300, 400, 500, 600, 800), (50, 100, 200, 400), 1000, 30)
QUICK = Config(True, 0.02, (2, 8), (1e-2, 1e-4, 1e-6, 1e-10), (8, 16, 32), (50, 100, 200, 400), (50, 100),
               128, (100, 200), (400, 800), (50, 100), ((10.0, 0.5, 0.3),), (50, 100), (50,), 200, 4)


def steady_cases(config: Config) -> dict[str, list[tuple[str, rc.Scene]]]:
    """Scene families (N' = 1 MN/m, R = 0.46 m, steel, mu = 0.3)."""

    def corrugated(wavelength, amplitude, axis=0.003, creep=1e-3):
        return rc.Scene(LOAD, creep=creep, axis_position=axis,
                        surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(wavelength, amplitude),)))

    def ka(wavelength):
        return f"k a = {2 * math.pi * A_HERTZ / wavelength:.2f}"

    families = {
        "Hertz/Carter": [("xi = 0.3 mu a/R", rc.Scene(LOAD, creep=0.3 * SATURATION)),
                         ("xi = 0.8 mu a/R", rc.Scene(LOAD, creep=0.8 * SATURATION))],
        "polynomial profile": [("quartic", rc.Scene(LOAD, creep=1e-3,
                                                    surface=rc.Surface(polynomial=(0, 0, 0, 0, -2e4)))),
                               # a falling quartic keeps the gap open: a cubic alone closes it 36 mm from the axis
                               ("cubic", rc.Scene(LOAD, creep=-8e-4,
                                                  surface=rc.Surface(polynomial=(0, 0, 0, 30.0, -2e4))))],
        "corrugation": [(f"100 mm / 50 um, {ka(0.1)}", corrugated(0.1, 50e-6)),
                        (f"40 mm / 20 um, {ka(0.04)}", corrugated(0.04, 20e-6)),
                        (f"20 mm / 5 um, {ka(0.02)}", corrugated(0.02, 5e-6)),
                        (f"10 mm / 20 um split, {ka(0.01)}", corrugated(0.01, 20e-6, axis=0.0045)),
                        # near full stick, where the discretised T' errs most relative to T'
                        (f"10 mm / 20 um split, {ka(0.01)}, xi = 0.01 mu a/R",
                         corrugated(0.01, 20e-6, axis=0.0045, creep=0.01 * SATURATION))],
        "velocity-dependent friction": [
            ("exponential B = 30 s/m, V = 20 m/s", rc.Scene(LOAD, creep=1e-3, rolling_speed=20.0,
                                                             friction=rc.ExponentialFalling(0.3, 0.4, 30.0))),
            ("exponential B = 3 s/m, V = 20 m/s", rc.Scene(LOAD, creep=0.3 * SATURATION, rolling_speed=20.0,
                                                            friction=rc.ExponentialFalling(0.3, 0.4, 3.0))),
            ("rational, V = 10 m/s", rc.Scene(LOAD, creep=0.7 * SATURATION, rolling_speed=10.0,
                                              friction=rc.RationalFalling(0.3, 0.2, 0.5))),
            # the corrugation family's split contact with the falling law: the slip iteration on both patches
            (f"exponential B = 3 s/m, V = 20 m/s, 10 mm / 20 um split, {ka(0.01)}",
             corrugated(0.01, 20e-6, axis=0.0045, creep=0.5 * SATURATION).replace(
                 rolling_speed=20.0, friction=rc.ExponentialFalling(0.3, 0.4, 3.0)))],
    }
    if config.quick:
        families = {"Hertz/Carter": families["Hertz/Carter"][:1],
                    "polynomial profile": families["polynomial profile"][:1],
                    "corrugation": families["corrugation"][1::2],
                    "velocity-dependent friction": families["velocity-dependent friction"][1:2]}
    return families


# --------------------------------------------------------------------------------------------------- records
@dataclass
class Row:
    """One measured setting (or auto's choice) on one case."""

    family: str
    case: str
    method: str
    label: str
    options: dict
    error_force: float
    error_pressure: float
    time: float
    model_cost: float = math.nan
    bound: float = math.nan
    auto: tuple[float, ...] = ()  # tolerances at which auto chose exactly this setting
    note: str = ""
    harmonics: int = 0  # surface harmonics of the scene (a term of the polynomial cost model)
    sharpness: float = 0.0  # friction_sharpness of the scene (sets the iteration counts of the cost model)
    patches: int = 1  # contact patches of the reference solution
    fmu_time: float = math.nan  # s per fmpy step of the contact FMU running this setting (pareto_measure.fmu_step_time)

    @property
    def error(self) -> float:
        return max(self.error_force, self.error_pressure)


@dataclass
class Reference:
    """Converged reference of a case and how it is obtained."""

    result: object
    how: str
    check: str = ""


@dataclass
class AutoChoice:
    """auto's choice at one requested tolerance on one case, and how it compares with the measured settings."""

    family: str
    case: str
    tolerance: float
    method: str
    label: str
    error: float
    time: float
    estimate: float
    met: bool
    cheapest: str = ""
    cheapest_time: float = math.nan  # of the fastest measured setting whose error is <= t
    chosen_time: float = math.nan  # of auto's setting run directly (steady cases: auto's time less the choice)
    paired: float = math.nan  # auto's time over the cheapest's, timed alternately (:func:`paired_ratio`)
    certified: str = ""
    certified_time: float = math.nan  # of the fastest measured setting whose a-priori bound is <= t
    certified_paired: float = math.nan  # auto's time over it, timed alternately
    fmu_time: float = math.nan  # s per fmpy step of the contact FMU with method = 0 (auto) and tolerance = t


def relative_errors(result, ref) -> tuple[float, float]:
    """Relative errors of T' and of the peak pressure p0 of ``result`` against ``ref``."""
    return (abs(result.tangential_force_per_length / ref.tangential_force_per_length - 1.0),
            abs(result.max_pressure / ref.max_pressure - 1.0))


def setting_label(method: str, options: dict) -> str:
    """A setting as the tables name it: the method, then its options."""
    if not options:
        return method.replace("_", " ")
    return method.replace("_", " ") + " " + ", ".join(f"{k} {v:g}" for k, v in options.items())


# ----------------------------------------------------------------------------------------------- references
SPLIT_REFERENCE_PLACEMENTS = 8


def split_reference(scene: rc.Scene, sizes: tuple[int, int], why: str) -> Reference:
    """A contact only the discretised solver treats: :func:`rollcontact.line.methods.discretised.steady.extrapolated`
    from n = sizes (first-order Richardson extrapolation of T', each level the mean over
    :data:`SPLIT_REFERENCE_PLACEMENTS` grid placements; p0, second order, the finer level's mean), at least twice as
    fine as every extrapolated setting measured; its uncertainty: the change from half the elements."""
    ref = rc.methods.discretised.steady.extrapolated(scene, sizes, SPLIT_REFERENCE_PLACEMENTS)
    half = rc.methods.discretised.steady.extrapolated(scene, tuple(n // 2 for n in sizes), SPLIT_REFERENCE_PLACEMENTS)
    change = abs(half.tangential_force_per_length / ref.tangential_force_per_length - 1.0)
    return Reference(ref, f"Richardson extrapolation of the discretised solver, n = {sizes[0]}/{sizes[1]} on a window "
                          f"fitted to the patches, each level the mean of {SPLIT_REFERENCE_PLACEMENTS} grid placements "
                          f"(polynomial invalid: {why[:40]}...)",
                     f"n = {sizes[0] // 2}/{sizes[1] // 2} differs from it by {change:.1e} in T'")


SPLIT_REFERENCE_NODES = 256
"""Slip nodes requested for the reference of a velocity-dependent law on a split contact (each patch runs twice
as many, ~3 s; its estimate ~2e-7).  The single patch's 1024 would run 2048 per patch in dense Newton steps."""


def steady_reference(scene: rc.Scene, config: Config) -> Reference:
    """The converged reference of a steady case and its cross-check (the module docstring of ``pareto.py``)."""
    if scene.surface.is_flat and scene.friction.is_constant:
        return Reference(rc.solve(scene, method="closed_form"), "closed form (exact)")
    nodes = config.reference_nodes
    if not scene.friction.is_constant and patch_count(rc.solve(scene, method="polynomial")) > 1:
        nodes = min(nodes, SPLIT_REFERENCE_NODES)
    poly = rc.solve(scene, method="polynomial", truncation=1e-12, nodes=nodes)
    if not poly.success:
        return split_reference(scene, config.split_reference, poly.message)
    how = (f"polynomial, tolerance 1e-12, {nodes} slip nodes (estimate {poly.info['error_estimate']:.1e})"
           if not scene.friction.is_constant else "polynomial, tolerance 1e-12")
    if config.richardson is None:
        return Reference(poly, how)
    if patch_count(poly) > 1 and not scene.friction.is_constant:
        return Reference(poly, f"{how}, {patch_count(poly)} patches", falling_split_check(scene, poly, config))
    if "patches" in poly.info:  # several patches: the split contacts' discretised reference is the cross-check
        sizes = config.split_reference
        check = rc.methods.discretised.steady.extrapolated(scene, sizes, SPLIT_REFERENCE_PLACEMENTS)
        diff = abs(check.tangential_force_per_length / poly.tangential_force_per_length - 1.0)
        return Reference(poly, f"{how}, {len(poly.info['patches'])} patches",
                         f"Richardson discretised n = {sizes[0]}/{sizes[1]}, each level the mean of "
                         f"{SPLIT_REFERENCE_PLACEMENTS} grid placements on a window fitted to the patches: T' within "
                         f"{diff:.1e}")
    a, offset = poly.contact_half_width, poly.contact_offset
    forces = [rc.solve(scene, method="discretised", elements=n,
                       window=(offset - 1.25 * a, offset + 1.25 * a)).tangential_force_per_length
              for n in config.richardson]
    extrapolated = 2.0 * forces[1] - forces[0]
    diff = abs(extrapolated / poly.tangential_force_per_length - 1.0)
    return Reference(poly, how, f"Richardson discretised n = {config.richardson[0]}/{config.richardson[1]}: "
                                f"T' within {diff:.1e}")


def patch_count(result) -> int:
    """Contact patches of a result (1 without a ``patches`` entry in its info)."""
    return len(result.info.get("patches", [None]))


def falling_split_check(scene: rc.Scene, poly, config: Config) -> str:
    """The discretised slip iteration's T' on the finer Richardson grid, scaled by the polynomial over the
    discretised Coulomb T' (mu = mu_s) on that grid: the ratio removes most of its first-order error, which the law
    hardly changes (``tests/test_split_friction.py``)."""
    n = config.richardson[1]
    coulomb = scene.replace(friction=rc.Coulomb(scene.friction.static_coefficient))
    disc, disc_c = (rc.solve(s, method="discretised", elements=n).tangential_force_per_length for s in (scene, coulomb))
    scaled = disc * rc.solve(coulomb, method="polynomial", truncation=1e-12).tangential_force_per_length / disc_c
    diff = abs(scaled / poly.tangential_force_per_length - 1.0)
    raw = abs(disc / poly.tangential_force_per_length - 1.0)
    return (f"discretised slip iteration n = {n} (automatic grid): T' within {raw:.1e}, scaled by the ratio of the "
            f"polynomial to the discretised Coulomb T' on that grid within {diff:.1e}")


# ------------------------------------------------------------------------------------------------- settings
SPLIT_NODES = 128
"""Largest slip nodes requested on a split contact (each patch runs twice as many, ~0.8 s a solve)."""


def steady_settings(scene: rc.Scene, config: Config, patches: int = 1) -> list[tuple[str, dict]]:
    """(method, options) to measure: every ladder setting of the applicable methods plus explicit orders (slip
    nodes up to :data:`SPLIT_NODES` on ``patches`` > 1)."""
    out = []
    if rc.METHODS["closed_form"].inapplicable(scene) is None:
        out.append(("closed_form", {}))
    if scene.friction.is_constant:
        out += [("polynomial", {"truncation": t}) for t in config.poly_tolerances]
        out += [("polynomial", {"order": n}) for n in config.poly_orders]
    else:
        # the node counts that run (requests below the law's floor run the floor: slip_nodes)
        largest = max(config.nodes) if patches == 1 else min(max(config.nodes), SPLIT_NODES)
        out += [("polynomial", options) for options in rc.METHODS["polynomial"].accuracy.ladder(scene)
                if options["nodes"] <= largest]
    sizes = config.elements if scene.friction.is_constant else config.structured_elements
    needed = DiscretisedAccuracy.resolution(scene)
    out += [("discretised", {"elements": n}) for n in sizes if n >= needed]
    out += [("discretised", options) for options in rc.METHODS["discretised"].accuracy.ladder(scene)
            if options.get("extrapolate") and options["elements"] in config.extrapolated_elements]
    return out


PLACEMENTS = (0.0, 0.25, 0.5, 0.75)
"""Shifts of the discretised grid, in elements, over which a discretised setting's error is the largest: the answer
at one n moves by about its error with where the patch edges fall in their elements
(``benchmarks/calibrate_discretised_estimate.py``), and in use (an FMU rolling along the rail) that placement is
arbitrary, so a setting meets t only if it does at every placement."""


def worst_placement_errors(scene: rc.Scene, method: str, options: dict, result, ref) -> tuple[float, float]:
    """The relative errors of T' and p0 of ``result``; for the discretised method on one grid the largest over the
    grid placements :data:`PLACEMENTS` (the window shifted by fractions of an element; the extrapolated setting
    averages over placements itself)."""
    errors = [relative_errors(result, ref)]
    if method == "discretised" and "grid" in result.info and not options.get("extrapolate"):
        grid = result.info["grid"]
        h = grid.element_width
        for shift in PLACEMENTS[1:]:
            window = (grid.x_min + shift * h, grid.x_max + shift * h)
            shifted = rc.solve(scene, method=method, **{**options, "elements": grid.elements, "window": window})
            errors.append(relative_errors(shifted, ref) if shifted.success else (math.inf, math.inf))
    return max(e[0] for e in errors), max(e[1] for e in errors)


# ------------------------------------------------------------------------------------------------- formats
def fmt_time(seconds: float) -> str:
    """A time [s] in ms or us, 3 significant digits; "-" when not finite."""
    if not math.isfinite(seconds):
        return "-"
    return f"{seconds * 1e3:.3g} ms" if seconds >= 1e-3 else f"{seconds * 1e6:.3g} us"


def fmt_error(value: float) -> str:
    """An error in the tables' format: "-" when not finite, "0" when exact."""
    return "-" if not math.isfinite(value) else ("0" if value == 0.0 else f"{value:.1e}")

