"""Speed-accuracy Pareto study: every method and setting on every scene family, error vs time, and auto's choices.

Run ``.venv/bin/python benchmarks/pareto.py [--quick]``: writes ``benchmarks/results/pareto.md`` (tables, headline
ratios, machine) and ``benchmarks/results/pareto.png`` (error vs time per family, the Pareto front of each case,
auto's choice at each requested tolerance).  ``--quick`` is a smoke test (< 60 s: one case per family, few
settings, small references); the full study takes several minutes.  One BLAS thread.

Error. Steady scenes: the larger relative error of T' and of the peak pressure p0 against a converged reference (the
contract of ``solve(scene, tolerance=t)``); for discretised settings the largest over four grid placements (the
window shifted by 0, 1/4, 1/2, 3/4 of an element, :data:`PLACEMENTS`): where the patch edges fall in their elements
moves the answer by about its error, and in use that placement is arbitrary. References: the closed form where exact
(Hertz/Carter); otherwise the polynomial method at truncation tolerance 1e-12 (1024 slip nodes for
velocity-dependent friction), cross-checked against the Richardson-extrapolated discretised solver (n = 800/1600 on
a window of +-1.25 a about the patch, whose edges then fall on element boundaries, as in
``tests/test_cross_methods.py``); for a split contact (several patches, ``rollcontact.multipatch``) against the
first-order Richardson extrapolation of the discretised T' from n = 2000/4000, each level the mean over 8 grid
placements on a window fitted to the patches; a contact the polynomial method cannot treat would take that
extrapolation as its reference (:func:`split_reference`), its uncertainty shown as the change from n = 1000/2000.
The extrapolated discretised settings (``extrapolate`` = m = 8, 16: n/2n, each level the mean over m placements)
average over placements themselves and are measured as they run. Instationary rolling (creep
control, ``xi = (0.5 + 0.3 sin(2 pi sigma/lambda)) mu a/R`` at lambda/a = 5..40, and a creep reversal ``0.9 sin`` at
lambda/a = 5, where the relaxation lag errs most; 64 host steps per cycle): max |T' - T'_ref| over the
last cycle in units of mu N', reference the extrapolating transient pair n = 500/1000 (nested grids, second order:
``bench_transient_pairs.py``; the plain transient's on the same finest grid shown). Every instationary setting, the
transients in the rows and the reference included, steps the FMU's model (quasi-static: ``transient`` = 0;
relaxation: 2; transient: ``method`` = 3, ``transient`` = 2, ``elements`` = n; pair: that model with the
extrapolating transient swapped in, :func:`pair_stepper`): the grids auto's transient runs on (window about +-1.77
a, the Hertz patch edges on element boundaries, ``ContactModel.prepare_grid``) and the model's overhead, so auto and
the rows compare like for like.

Time. Median over repeated calls (timeit-style batches, at least 3 samples); discretised solves with the caches of
influence matrices emptied first (a first solve on a new grid, as for a moving axis); instationary: median per host
step. FMU: microseconds per fmpy step (set inputs, doStep, get outputs) against an empty pythonfmu FMU built in the
same run (``common.py``): for every steady setting that an FMU parameter selects (closed form: ``method`` = 1;
polynomial: 2 with its ``tolerance`` or ``polynomial_order``; discretised: 3 with ``elements``) and for auto
(``method`` = 0, ``tolerance`` = t), a fresh contact FMU reading the case's scene from a scene file
(``common.scene_toml``; its model solves exactly the case's scene) with the case's load, creep and speed as
constant inputs, stepped by 1 ns so the axis stays where the case puts it (``common.steady_step_time``: caches warm
after a first step, as along a run); and a few cases with varying inputs against the empty FMU (``fmu_study``).  The
machine is shared and noisy: compare ratios measured in the same run, not absolute times across runs.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import statistics
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import common  # before numpy: limits BLAS to one thread
import numpy as np
import scipy
from scipy import optimize, stats

import rollcontact as rc
from rollcontact import api
from rollcontact.closed_form import hertz
from rollcontact.instationary import (
    LAG_MEMORY,
    InstationaryModel,
    creep_envelope,
    lag_error_bound,
    relaxation_length,
)
from rollcontact.model import (
    INSTATIONARY_CODES,
    ContactModel,
    ContactParameters,
    transient_model_error,
    transient_setting,
)

RESULTS = common.RESULTS
TOLERANCES = (1e-2, 1e-3, 1e-4)
ERROR_FLOOR = 1e-16  # plotted instead of an exact 0
LOWEST_COST_SLACK = 1.5  # auto's time within this factor of the cheapest measured setting counts as the lowest cost
ESTAR = rc.Material().contact_modulus
LOAD = 1e6  # N' [N/m] of the steady cases
A_HERTZ = hertz(LOAD, 0.46, ESTAR)[0]
SATURATION = 0.3 * A_HERTZ / 0.46  # Carter's saturation creep mu a / R
CONTACT_WIDTH = common.CONTACT_WIDTH  # m, the FMU's default lateral width


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


FULL = Config(False, 0.3, (1, 2, 4, 8, 16, 32), api.POLYNOMIAL_TOLERANCES, api.SLIP_NODES,
              api.DISCRETISED_ELEMENTS, (50, 100, 200, 400, 800), 1024, (800, 1600), (2000, 4000),
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
                               ("cubic", rc.Scene(LOAD, creep=-8e-4, surface=rc.Surface(polynomial=(0, 0, 0, 30.0))))],
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


# ------------------------------------------------------------------------------------------------------ timing
BATCH_SECONDS = 2e-3  # s: the least duration of one timing sample (timeit-style batches of calls)


def solve_time(function, budget: float) -> float:
    """Median time per call [s] of ``function`` as the study times a solve: after a warm-up call, samples of
    batches of calls lasting at least ~2 ms (:data:`BATCH_SECONDS`), at least 3 and up to 200 within ``budget`` [s]
    (:func:`common.median_time`)."""
    return common.median_time(function, min_repeats=3, min_seconds=budget, warmups=1, batch_seconds=BATCH_SECONDS,
                              max_repeats=200)


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
    sharpness: float = 0.0  # api.friction_sharpness of the scene (sets the iteration counts of the cost model)
    patches: int = 1  # contact patches of the reference solution
    fmu_time: float = math.nan  # s per fmpy step of the contact FMU running this setting (:func:`fmu_step_time`)

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


PAIRED_ROUNDS = 3


def paired_ratio(first, second) -> float:
    """Median over :data:`PAIRED_ROUNDS` of ``first() / second()``, the two timings (callables returning seconds)
    taken one after the other: the shared machine's speed drifts over the minutes between a case's rows, so the
    comparison of auto with the cheapest setting is timed again, alternately."""
    return statistics.median(first() / second() for _ in range(PAIRED_ROUNDS))


def with_cheapest(choice: AutoChoice, rows: list[Row], timer, auto_timer) -> AutoChoice:
    """``choice`` with the fastest of the case's measured ``rows`` whose error meets its tolerance noted, and auto's
    time over it timed alternately (``timer(row)`` and ``auto_timer()`` time a row's setting and auto, [s]); also
    the fastest whose a-priori bound meets it (what auto can know before solving), timed alternately likewise."""
    fastest = {}
    for kind, meets in (("measured", lambda r: r.error <= choice.tolerance),
                        ("certified", lambda r: r.bound <= choice.tolerance)):
        candidates = [r for r in rows if meets(r)]
        if candidates:
            fastest[kind] = min(candidates, key=lambda r: r.time)
    if "measured" in fastest:
        best = fastest["measured"]
        choice.cheapest = f"{best.label} ({fmt_time(best.time)})"
        choice.cheapest_time = best.time
        if choice.error <= choice.tolerance:
            choice.paired = paired_ratio(auto_timer, lambda: timer(best))
    if "certified" in fastest:
        best = fastest["certified"]
        choice.certified = f"{best.label} ({fmt_time(best.time)})"
        choice.certified_time = best.time
        if choice.error <= choice.tolerance:
            choice.certified_paired = (choice.paired if best is fastest.get("measured")
                                       else paired_ratio(auto_timer, lambda: timer(best)))
    return choice


def relative_errors(result, ref) -> tuple[float, float]:
    return (abs(result.tangential_force_per_length / ref.tangential_force_per_length - 1.0),
            abs(result.max_pressure / ref.max_pressure - 1.0))


def setting_label(method: str, options: dict) -> str:
    if not options:
        return method.replace("_", " ")
    return method.replace("_", " ") + " " + ", ".join(f"{k} {v:g}" for k, v in options.items())


# ----------------------------------------------------------------------------------------------- references
SPLIT_REFERENCE_PLACEMENTS = 8


def split_reference(scene: rc.Scene, sizes: tuple[int, int], why: str) -> Reference:
    """A contact only the discretised solver treats: :func:`rollcontact.discretised.extrapolated` from n = sizes
    (first-order Richardson extrapolation of T', each level the mean over :data:`SPLIT_REFERENCE_PLACEMENTS` grid
    placements; p0, second order, the finer level's mean), at least twice as fine as every extrapolated setting
    measured; its uncertainty: the change from half the elements."""
    ref = rc.discretised.extrapolated(scene, sizes, SPLIT_REFERENCE_PLACEMENTS)
    half = rc.discretised.extrapolated(scene, tuple(n // 2 for n in sizes), SPLIT_REFERENCE_PLACEMENTS)
    change = abs(half.tangential_force_per_length / ref.tangential_force_per_length - 1.0)
    return Reference(ref, f"Richardson extrapolation of the discretised solver, n = {sizes[0]}/{sizes[1]} on a window "
                          f"fitted to the patches, each level the mean of {SPLIT_REFERENCE_PLACEMENTS} grid placements "
                          f"(polynomial invalid: {why[:40]}...)",
                     f"n = {sizes[0] // 2}/{sizes[1] // 2} differs from it by {change:.1e} in T'")


SPLIT_REFERENCE_NODES = 256
"""Slip nodes requested for the reference of a velocity-dependent law on a split contact (each patch runs twice
as many, ~3 s; its estimate ~2e-7).  The single patch's 1024 would run 2048 per patch in dense Newton steps."""


def steady_reference(scene: rc.Scene, config: Config) -> Reference:
    if scene.surface.is_flat and scene.friction.is_constant:
        return Reference(rc.solve(scene, method="closed_form"), "closed form (exact)")
    nodes = config.reference_nodes
    if not scene.friction.is_constant and patch_count(rc.solve(scene, method="polynomial")) > 1:
        nodes = min(nodes, SPLIT_REFERENCE_NODES)
    poly = rc.solve(scene, method="polynomial", tolerance=1e-12, nodes=nodes)
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
        check = rc.discretised.extrapolated(scene, sizes, SPLIT_REFERENCE_PLACEMENTS)
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
    return len(result.info.get("patches", [None]))


def falling_split_check(scene: rc.Scene, poly, config: Config) -> str:
    """The discretised slip iteration's T' on the finer Richardson grid, scaled by the polynomial over the
    discretised Coulomb T' (mu = mu_s) on that grid: the ratio removes most of its first-order error, which the law
    hardly changes (``tests/test_split_friction.py``)."""
    n = config.richardson[1]
    coulomb = scene.replace(friction=rc.Coulomb(scene.friction.static_coefficient))
    disc, disc_c = (rc.solve(s, method="discretised", elements=n).tangential_force_per_length for s in (scene, coulomb))
    scaled = disc * rc.solve(coulomb, method="polynomial", tolerance=1e-12).tangential_force_per_length / disc_c
    diff = abs(scaled / poly.tangential_force_per_length - 1.0)
    raw = abs(disc / poly.tangential_force_per_length - 1.0)
    return (f"discretised slip iteration n = {n} (automatic grid): T' within {raw:.1e}, scaled by the ratio of the "
            f"polynomial to the discretised Coulomb T' on that grid within {diff:.1e}")


# --------------------------------------------------------------------------------------------- steady study
SPLIT_NODES = 128
"""Largest slip nodes requested on a split contact (each patch runs twice as many, ~0.8 s a solve)."""


def steady_settings(scene: rc.Scene, config: Config, patches: int = 1) -> list[tuple[str, dict]]:
    """(method, options) to measure: every ladder setting of the applicable methods plus explicit orders (slip
    nodes up to :data:`SPLIT_NODES` on ``patches`` > 1)."""
    out = []
    if rc.METHODS["closed_form"].inapplicable(scene) is None:
        out.append(("closed_form", {}))
    if scene.friction.is_constant:
        out += [("polynomial", {"tolerance": t}) for t in config.poly_tolerances]
        out += [("polynomial", {"order": n}) for n in config.poly_orders]
    else:
        # the node counts that run (requests below the law's floor run the floor: api.slip_nodes)
        largest = max(config.nodes) if patches == 1 else min(max(config.nodes), SPLIT_NODES)
        out += [("polynomial", options) for options in rc.METHODS["polynomial"].accuracy.ladder(scene)
                if options["nodes"] <= largest]
    sizes = config.elements if scene.friction.is_constant else config.structured_elements
    needed = api.DiscretisedAccuracy.resolution(scene)
    out += [("discretised", {"elements": n}) for n in sizes if n >= needed]
    out += [("discretised", options) for options in rc.METHODS["discretised"].accuracy.ladder(scene)
            if options.get("extrapolate") and options["elements"] in config.extrapolated_elements]
    return out


PLACEMENTS = (0.0, 0.25, 0.5, 0.75)
"""Shifts of the discretised grid, in elements, over which a discretised setting's error is the largest: the answer
at one n moves by about its error with where the patch edges fall in their elements
(``benchmarks/bench_discretised_estimate.py``), and in use (an FMU rolling along the rail) that placement is
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


@dataclass(frozen=True)
class FmuBench:
    """The FMUs built for this run (unzip directories) and a folder for the scene files of the steady cases."""

    empty: str
    contact: str
    folder: Path

    def scene_file(self, scene: rc.Scene) -> str:
        """Path of a TOML scene file the contact FMU reads as ``scene``'s (:func:`common.scene_toml`)."""
        handle, path = tempfile.mkstemp(suffix=".toml", dir=self.folder)
        with os.fdopen(handle, "w") as file:
            file.write(common.scene_toml(scene))
        return path


def fmu_parameters(method: str, options: dict) -> dict | None:
    """The contact FMU's parameters that run ``method`` with ``options``; None where no parameter sets the option
    (the slip iteration's nodes, the extrapolated discretised pairs)."""
    if method == "closed_form" and not options:
        return {"method": 1}
    if method == "polynomial" and set(options) == {"tolerance"}:
        # the FMU's tolerance picks the loosest truncation tolerance <= t: t itself for api.POLYNOMIAL_TOLERANCES
        return {"method": 2, "tolerance": options["tolerance"]}
    if method == "polynomial" and set(options) == {"order"}:
        return {"method": 2, "polynomial_order": options["order"]}
    if method == "discretised" and set(options) == {"elements"}:
        return {"method": 3, "elements": options["elements"]}
    return None


def fmu_step_time(fmu: FmuBench | None, scene_file: str, scene: rc.Scene, parameters: dict | None,
                  config: Config) -> float:
    """Seconds per fmpy step of a fresh contact FMU reading ``scene_file`` with ``parameters``, its axis at the
    scene's and its inputs the scene's load (over :data:`CONTACT_WIDTH`), creep and speed
    (:func:`common.steady_step_time`); NaN without an FMU, without parameters for the setting, or where a step is
    discarded.

    The FMU's model runs in this process on the ``rollcontact`` imported here (the slave's module docstring), so
    every step of a setting that may run the discretised solver (``method`` 0 and 3) starts with the influence
    matrices emptied, as :func:`common.cold` times its solve(): a first solve on its grid, as along a run on a
    corrugation, where the grid moves with the patch."""
    if fmu is None or parameters is None:
        return math.nan
    us, discards = common.steady_step_time(
        fmu.contact, {"scene_file": scene_file, "initial_position": -scene.axis_position,
                      "contact_width": CONTACT_WIDTH, **parameters},
        (scene.normal_load_per_length * CONTACT_WIDTH, scene.creep), scene.rolling_speed, config.budget,
        before_step=common.influence_cache_clear() if parameters["method"] in (0, 3) else None)
    return math.nan if discards else us * 1e-6


def measure_case(family: str, label: str, scene: rc.Scene, config: Config,
                 fmu: FmuBench | None = None) -> tuple[list[Row], list[AutoChoice], Reference]:
    ref = steady_reference(scene, config)
    patches = patch_count(ref.result)
    rows = []
    scene_file = fmu.scene_file(scene) if fmu is not None else ""
    for method, options in steady_settings(scene, config, patches):
        result = rc.solve(scene, method=method, **options)
        if not result.success:
            rows.append(Row(family, label, method, setting_label(method, options), options, math.nan, math.nan,
                            math.nan, note=f"fails: {result.message[:60]}"))
            continue
        ef, ep = worst_placement_errors(scene, method, options, result, ref.result)
        model = rc.METHODS[method].accuracy
        t = solve_time(common.cold(lambda m=method, o=options: rc.solve(scene, method=m, **o), method), config.budget)
        rows.append(Row(family, label, method, setting_label(method, options), options, ef, ep, t,
                        model.cost(scene, options), model.error(scene, options),
                        harmonics=len(scene.surface.harmonics),
                        sharpness=0.0 if scene.friction.is_constant else api.friction_sharpness(scene),
                        patches=patches,
                        fmu_time=fmu_step_time(fmu, scene_file, scene, fmu_parameters(method, options), config)))
    choices = []
    for tolerance in TOLERANCES:
        auto = rc.solve(scene, tolerance=tolerance)
        ef, ep = worst_placement_errors(scene, auto.method, auto.info["setting"], auto, ref.result)
        options = auto.info["setting"]

        def auto_timer(method=auto.method, tol=tolerance):
            return solve_time(common.cold(lambda: rc.solve(scene, tolerance=tol), method), config.budget)

        def timer(row):
            return solve_time(common.cold(lambda: rc.solve(scene, method=row.method, **row.options), row.method),
                              config.budget)

        choice = AutoChoice(family, label, tolerance, auto.method, setting_label(auto.method, options), max(ef, ep),
                            auto_timer(), auto.info["error_estimate"], auto.info["tolerance_met"],
                            fmu_time=fmu_step_time(fmu, scene_file, scene, {"method": 0, "tolerance": tolerance},
                                                   config))
        for row in rows:
            if row.method == auto.method and row.options == options:
                row.auto += (tolerance,)
                choice.chosen_time = row.time
        choices.append(with_cheapest(choice, rows, timer, auto_timer))
    return rows, choices, ref


# --------------------------------------------------------------------------------------- instationary study
LOAD_I = 1e7  # N' [N/m], as bench_instationary.py
MU_I, R_I, SPEED = 0.3, 0.46, 10.0
A_I = hertz(LOAD_I, R_I, ESTAR)[0]
SATURATION_I = MU_I * A_I / R_I
STEPS_PER_CYCLE = 64


def creep_signal(wavelength: float, mean: float = 0.5, amplitude: float = 0.3) -> tuple[np.ndarray, float, int]:
    """Creep ``(mean + amplitude sin(2 pi sigma/lambda)) mu a/R`` per host step, the step [s] and the index of the
    first step of the measured (last) cycle."""
    cycles = max(1, math.ceil(40.0 / wavelength)) + 1  # >= 40 a of settling: the lag (~5 a) has decayed
    k = np.arange(1, cycles * STEPS_PER_CYCLE + 1)
    xi = SATURATION_I * (mean + amplitude * np.sin(2.0 * np.pi * k / STEPS_PER_CYCLE))
    dt = wavelength * A_I / STEPS_PER_CYCLE / SPEED
    return xi, dt, (cycles - 1) * STEPS_PER_CYCLE


def run_instationary(step, wavelength: float, mean: float = 0.5, amplitude: float = 0.3) -> tuple[np.ndarray, float]:
    """T' [N/m] over the measured cycle of :func:`creep_signal` and the median time per host step [s] of
    ``step(xi, dt) -> T'``."""
    xi, dt, first = creep_signal(wavelength, mean, amplitude)
    forces, times = [], []
    for i, value in enumerate(xi):
        t0 = time.perf_counter()
        force = step(value, dt)
        times.append(time.perf_counter() - t0)
        if i >= first:
            forces.append(force)
    return np.array(forces), statistics.median(times)


def model_stepper(**parameters):
    """``step(xi, dt) -> T'`` of the FMU's stepping model with these parameters; ``step.model`` is the
    :class:`ContactModel`, ``step.used`` the ``method_used`` of every step."""
    model = ContactModel(ContactParameters(radius=R_I, contact_width=CONTACT_WIDTH, friction_coefficient=MU_I,
                                           **parameters))
    clock = [0.0]

    def step(xi, dt):
        out = model.step(clock[0], dt, LOAD_I * CONTACT_WIDTH, xi, SPEED)
        clock[0] += dt
        step.used.append(out.method_used)
        return out.tangential_force / CONTACT_WIDTH
    step.model, step.used = model, []
    return step


def instationary_stepper(kind: str, elements: int = 0, tolerance: float = 0.0):
    """``step(xi, dt) -> T'`` of the FMU's stepping model: quasi-static Carter (``transient`` = 0), the relaxation
    lag (``transient`` = 2), the discretised transient with ``elements`` (0: 100; ``method`` = 3, ``transient`` = 2)
    or auto (``transient`` = 1) at ``tolerance``: every setting, auto's included, pays the same model overhead.

    The transient runs on the grid auto's transient builds for the same n (aligned to the load).  Over the measured
    cycle it agrees with auto forced to that n (``elements`` = n) to 1e-7 mu N' (measured for n = 100, 200 at
    lambda/a = 5, 40): auto starts from steady rolling, this from no traction, and the start has decayed.
    """
    if kind == "transient pair":
        return pair_stepper(elements)
    parameters = {"quasi-static": {"transient": 0}, "relaxation": {"transient": 2},
                  "transient": {"method": 3, "transient": 2, "elements": elements},
                  "auto": {"transient": 1, "tolerance": tolerance}}
    return model_stepper(**parameters[kind])


def pair_stepper(elements: int):
    """The FMU's model (``method`` = 3, ``transient`` = 2) with the extrapolating transient of ``elements``/2 and
    ``elements`` in place of its plain one: what auto builds for a tolerance below about 4e-3."""
    step = model_stepper(method=3, transient=2, elements=elements)
    model = step.model
    model.instationary = InstationaryModel(model.radius, model.contact_modulus, model.mu, mode="transient",
                                           elements=elements, extrapolate=True)
    return step


def lag_bounds(wavelength: float, mean: float = 0.5, amplitude: float = 0.3) -> np.ndarray:
    """The relaxation lag's error bound [1 of mu N'] at each step of the measured cycle of :func:`creep_signal`, as
    auto's model computes it: :func:`rollcontact.instationary.lag_error_bound` of the creep envelope
    (:func:`rollcontact.instationary.creep_envelope`) over the host steps."""
    xi, _, first = creep_signal(wavelength, mean, amplitude)
    memory = LAG_MEMORY * relaxation_length(0.0, LOAD_I, R_I, ESTAR, MU_I, R_I)
    step = wavelength * A_I / STEPS_PER_CYCLE / memory
    envelope, bounds = None, []
    for value in xi:
        envelope = creep_envelope(envelope, value / SATURATION_I, step)
        bounds.append(lag_error_bound(envelope))
    return np.array(bounds[first:])


def instationary_bound(kind: str, elements: int, signal: tuple[float, float, float]) -> float:
    """The model's a-priori error [1 of mu N'] of an instationary setting, as auto's choice uses it: the relaxation
    lag's bound for the signal's creep swing (the largest over the measured cycle of :func:`lag_bounds`), the
    transient's ``C/n`` and the pair's ``C/n^2``; none for quasi-static steps (auto switches them off by the
    stationarity measure instead)."""
    if kind == "relaxation":
        return float(lag_bounds(*signal).max())
    if kind.startswith("transient"):
        return transient_model_error(elements, kind == "transient pair")
    return math.nan


def instationary_study(config: Config) -> tuple[list[Row], list[AutoChoice], list[tuple[str, str, str]]]:
    rows, choices, references = [], [], []
    limit = MU_I * LOAD_I
    fine = config.transient_reference
    # auto's own pairs too: the cheapest setting whose bound meets t is then among the rows
    pairs = sorted(set(config.transient_pairs) | {n for n, pair in map(transient_setting, TOLERANCES) if pair})
    for signal in config.signals:
        wavelength, mean, amplitude = signal
        case = f"lambda/a = {wavelength:g}" + ("" if (mean, amplitude) == (0.5, 0.3) else
                                              f", xi = ({mean:g} + {amplitude:g} sin) mu a/R")
        reference = pair_stepper(fine)
        ref, ref_time = run_instationary(reference, *signal)
        plain = instationary_stepper("transient", fine)
        plain_forces, plain_time = run_instationary(plain, *signal)
        window = reference.model.instationary.solver.grid.x_max / A_I
        references.append((case, f"the extrapolating transient pair n = {fine // 2}/{fine} (nested grids, window "
                                 f"+-{window:.3f} a, the Hertz patch edges on element boundaries of both; second "
                                 "order, benchmarks/bench_transient_pairs.py) in the FMU model",
                           f"the plain transient n = {fine} differs from it by "
                           f"{np.abs(plain_forces - ref).max() / limit:.1e} mu N'"))
        settings = [("quasi-static", {}), ("relaxation", {})]
        settings += [("transient", {"elements": n}) for n in config.transient_elements]
        settings += [("transient pair", {"elements": n}) for n in pairs]
        for kind, options in settings:
            n = options.get("elements", 0)
            forces, t = ((plain_forces, plain_time) if (kind, n) == ("transient", fine) else
                         run_instationary(instationary_stepper(kind, n), *signal))
            rows.append(Row("instationary", case, kind, setting_label(kind, options), options,
                            float(np.abs(forces - ref).max() / limit), 0.0, t,
                            bound=instationary_bound(kind, n, signal)))
        case_rows = [r for r in rows if r.case == case]
        for tolerance in TOLERANCES:
            stepper = instationary_stepper("auto", tolerance=tolerance)
            forces, t = run_instationary(stepper, *signal)
            measured = stepper.used[-STEPS_PER_CYCLE:]
            models = [m for m in (stepper.model.lag, stepper.model.instationary) if m is not None]
            shares, kinds = [], {}
            for model in models:
                kind = "transient pair" if model.extrapolate else model.mode
                name = kind + (f" n = {model.elements // 2}/{model.elements}" if model.extrapolate else
                               f" n = {model.elements}" if model.mode == "transient" else "")
                code = INSTATIONARY_CODES[model.mode]
                kinds[code] = (kind, model.elements)
                if code in measured:
                    shares.append(f"{measured.count(code) / len(measured):.0%} {name}")
            error = float(np.abs(forces - ref).max() / limit)
            choice = AutoChoice("instationary", case, tolerance, "auto",
                                f"FMU auto ({', '.join(shares) or 'quasi-static'})", error, t, math.nan,
                                error <= tolerance)
            if len(set(measured)) == 1 and measured[0] in kinds:  # every measured step ran one model: its row
                kind, elements = kinds[measured[0]]
                for row in case_rows:
                    if row.method == kind and row.options.get("elements", elements) == elements:
                        choice.chosen_time = row.time
            choices.append(with_cheapest(
                choice, case_rows,
                lambda row, sig=signal: run_instationary(
                    instationary_stepper(row.method, row.options.get("elements", 0)), *sig)[1],
                lambda tol=tolerance, sig=signal: run_instationary(
                    instationary_stepper("auto", tolerance=tol), *sig)[1]))
    return rows, choices, references


def richardson(coarse: np.ndarray, fine: np.ndarray, refinement: float) -> np.ndarray:
    """T' extrapolated to zero element size from two grids, first order: the transient's observed order is
    0.97-0.98 at lambda/a = 5..40 (``benchmarks/bench_transient_auto.py``, from n, 2n, 4n), the steady discretised
    T' is first order in the elements across the contact (``benchmarks/bench_discretised_estimate.py``)."""
    return fine + (fine - coarse) / (refinement - 1.0)


# ---------------------------------------------------------------------------------------------------- FMU steps
def fmu_study(config: Config, fmu: FmuBench) -> list[tuple[str, float, float, int, set]]:
    """(label, median us/step, ratio to the empty FMU, discarded steps, method_used codes) per case."""
    corrugation, case = common.FMU_CORRUGATION, common.Case
    empty, contact = fmu.empty, fmu.contact
    cases = [case("empty pythonfmu FMU", empty, {}, 200, 1.0),
             case("closed form (method 1)", contact, {"method": 1}, 200, 20.0),
             case("polynomial, corrugation 40 mm / 20 um (method 2)", contact, {"method": 2, **corrugation}, 10, 1.0),
             case("auto, corrugation, tolerance 1e-3 (method 0)", contact,
                  {"method": 0, "tolerance": 1e-3, **corrugation}, 10, 1.0),
             case("falling friction, auto (method 0)", contact, {"method": 0, "friction_law": 1}, 2, 20.0),
             case("falling friction, auto, tolerance 1e-3 (method 0)", contact,
                  {"method": 0, "friction_law": 1, "tolerance": 1e-3}, 2, 20.0),
             case("discretised, corrugation (method 3)", contact, {"method": 3, **corrugation}, 2, 1.0),
             case("relaxation lag (transient 2)", contact, {"transient": 2}, 50, 20.0),
             case("discretised transient n = 100 (method 3, transient 2)", contact,
                  {"method": 3, "transient": 2}, 5, 20.0)]
    common.run_interleaved(cases, config.fmu_rounds)
    floor = statistics.median(cases[0].times)
    out = [(c.label, statistics.median(c.times), statistics.median(c.times) / floor, c.discards,
            c.methods_used) for c in cases]
    for c in cases:
        c.free()
    return out


# ------------------------------------------------------------------------------------------------- analysis
def pareto_front(rows: list[Row]) -> list[Row]:
    """Rows not dominated in (time, error), by time."""
    front, best = [], math.inf
    for row in sorted((r for r in rows if math.isfinite(r.time) and math.isfinite(r.error)),
                      key=lambda r: (r.time, r.error)):
        if row.error < best:
            front.append(row)
            best = row.error
    return front


def envelope(rows: list[Row], row: Row) -> float:
    """Largest error of this and the finer settings of the same method on the same case (listed after it)."""
    same = [r for r in rows if r.case == row.case and r.method == row.method and r.family == row.family
            and r.options.keys() == row.options.keys()]
    return max(r.error for r in same[same.index(row):])


@dataclass(frozen=True)
class EqualAccuracy:
    """One case's discretised/polynomial time ratio at an accuracy level (:func:`equal_accuracy_ratios`)."""

    case: str
    ratio: float
    polynomial: Row  # the fastest polynomial setting meeting the level
    discretised: Row  # the fastest discretised setting converged to it, else the slowest measured
    lower_bound: bool  # no discretised setting measured converged to the level: the ratio is at least this


def equal_accuracy_ratios(rows: list[Row], level: float, extrapolated: bool) -> list[EqualAccuracy]:
    """Per case: time of the cheapest discretised setting of one kind (single grids, or the extrapolated pairs)
    converged to ``level`` (its error and its finer settings' at most ``level``: :func:`envelope`) over the
    cheapest polynomial setting meeting it; where none converged, the slowest measured one, a lower bound."""
    out = []
    for case in dict.fromkeys(r.case for r in rows):
        poly = [r for r in rows if r.case == case and r.method == "polynomial" and r.error <= level]
        disc = [r for r in rows if r.case == case and r.method == "discretised" and math.isfinite(r.error)
                and bool(r.options.get("extrapolate")) == extrapolated]
        if not poly or not disc:
            continue
        fastest = min(poly, key=lambda r: r.time)
        converged = [r for r in disc if envelope(rows, r) <= level]
        best = min(converged, key=lambda r: r.time) if converged else max(disc, key=lambda r: r.time)
        out.append(EqualAccuracy(case, best.time / fastest.time, fastest, best, not converged))
    return out


def equal_accuracy_lines(rows: list[Row]) -> tuple[list[str], list[str]]:
    """Headline lines of the discretised/polynomial ratios at 1e-2 and 1e-3, and their table per case."""
    lines, table = [], []
    steady = [r for r in rows if r.family != "instationary"]
    for extrapolated, kind in ((False, "single-grid"), (True, "extrapolated (8 or 16 placements)")):
        for level in (1e-2, 1e-3):
            ratios = equal_accuracy_ratios(steady, level, extrapolated)
            if not ratios:
                continue
            values = [q.ratio for q in ratios]
            bounds = sum(q.lower_bound for q in ratios)
            lines.append(f"- Discretised vs polynomial at equal accuracy {level:.0e} (time of the cheapest {kind} "
                         f"discretised setting converged to it over the polynomial's): median "
                         f"{statistics.median(values):.3g}x, range {min(values):.3g}-{max(values):.3g}x over "
                         f"{len(values)} cases" + (f" ({bounds} of them lower bounds: no {kind} setting measured "
                                                   "converged to it)" if bounds else ""))
            for q in ratios:
                errs = f" (errs {fmt_error(q.discretised.error)})" if q.lower_bound else ""
                table.append(f"| {q.case} | {level:.0e} | {kind} | {q.polynomial.label} | "
                             f"{fmt_time(q.polynomial.time)} | {q.discretised.label}{errs} | "
                             f"{fmt_time(q.discretised.time)} | {'>= ' if q.lower_bound else ''}{q.ratio:.3g} |")
    if table:
        table = ["", "Per case (the fastest polynomial setting meeting the level; the fastest discretised setting "
                 "whose error, and that of its finer settings, meets it; '>=' where none measured did, against the "
                 "finest):", "", "| case | level | discretised kind | polynomial | time | discretised | time | "
                 "ratio |", "|---|---|---|---|---|---|---|---|", *table, ""]
    return lines, table


def fit_costs(rows: list[Row]) -> list[tuple[str, str, str]]:
    """Least-squares constants of the cost model (relative residuals) next to the ones in api.py."""

    def fit(columns, times):
        a = np.column_stack(columns) / times[:, None]
        return optimize.nnls(a, np.ones(times.size))[0]

    out = []
    rows = [r for r in rows if math.isfinite(r.time)]
    closed = [r.time for r in rows if r.method == "closed_form"]
    if closed:
        out.append(("CLOSED_FORM_COST", f"{api.CLOSED_FORM_COST:.3g}", f"{statistics.median(closed):.3g}"))
    coulomb = [r for r in rows if r.method == "polynomial" and "nodes" not in r.options]
    if len(coulomb) > 2:
        harmonics = np.array([r.harmonics for r in coulomb], dtype=float)
        base, per = fit([np.ones(len(coulomb)), harmonics], np.array([r.time for r in coulomb]))
        out.append(("POLYNOMIAL_COST, POLYNOMIAL_HARMONIC_COST",
                    f"{api.POLYNOMIAL_COST:.3g}, {api.POLYNOMIAL_HARMONIC_COST:.3g}", f"{base:.3g}, {per:.3g}"))
    direct = [r for r in rows if r.method == "discretised" and r.sharpness == 0.0 and not r.options.get("extrapolate")]
    if len(direct) > 3:
        n = np.array([r.options["elements"] for r in direct], dtype=float)
        fitted = fit([np.ones(n.size), n**2, n**3], np.array([r.time for r in direct]))
        out.append(("DIRECT_COST (a, b, c)", ", ".join(f"{c:.3g}" for c in api.DIRECT_COST),
                    ", ".join(f"{c:.3g}" for c in fitted)))
    # velocity-dependent friction: times per modelled iteration (the iteration counts are part of the model)
    # on one patch: a split contact runs each patch's iteration in sweeps, which the model does not count
    structured = [r for r in rows if r.method == "discretised" and r.sharpness > 0.0 and r.patches == 1]
    if len(structured) > 3:
        n = np.array([r.options["elements"] for r in structured], dtype=float)
        iterations = np.array([api.STRUCTURED_ITERATIONS[0] + api.STRUCTURED_ITERATIONS[1] * r.sharpness
                               for r in structured])
        fitted = fit([np.ones(n.size), n**2, n**3], np.array([r.time for r in structured]) / iterations)
        out.append(("STRUCTURED_COST (a, b, c) per iteration", ", ".join(f"{c:.3g}" for c in api.STRUCTURED_COST),
                    ", ".join(f"{c:.3g}" for c in fitted)))
    velocity = [r for r in rows if r.method == "polynomial" and "nodes" in r.options and r.patches == 1]
    if len(velocity) > 3:
        nodes = np.array([r.options["nodes"] for r in velocity], dtype=float)
        iterations = np.array([api.SLIP_ITERATIONS[0] + api.SLIP_ITERATIONS[1] * r.sharpness for r in velocity])
        extra = (np.array([r.time for r in velocity]) - api.POLYNOMIAL_COST) / iterations
        fitted = fit([np.ones(nodes.size), nodes**2, nodes**3], np.maximum(extra, 1e-7))
        out.append(("SLIP_COST (a, b, c) per iteration", ", ".join(f"{c:.3g}" for c in api.SLIP_COST),
                    ", ".join(f"{c:.3g}" for c in fitted)))
    return out


def rank_agreement(rows: list[Row]) -> tuple[float, float, int]:
    """Spearman correlation of model cost and measured time over all settings, and the fraction of same-case
    pairs whose measured times differ by more than 30 % that the model orders the same way."""
    good = [r for r in rows if math.isfinite(r.model_cost) and math.isfinite(r.time)]
    rho = stats.spearmanr([r.model_cost for r in good], [r.time for r in good])[0]
    agree = total = 0
    for i, r in enumerate(good):
        for s in good[i + 1:]:
            if r.case != s.case or max(r.time, s.time) < 1.3 * min(r.time, s.time):
                continue
            total += 1
            agree += (r.model_cost < s.model_cost) == (r.time < s.time)
    return float(rho), agree / total if total else math.nan, total


# ------------------------------------------------------------------------------------------------- reporting
def machine(load: float) -> list[str]:
    """The machine's description; ``load``: the 1-minute load average read before the study started (read at the
    end it would count the study's own process)."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            cpu = next(line.split(":", 1)[1].strip() for line in fh if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
    return [f"- CPU: {cpu}, {os.cpu_count()} logical cores (shared with other jobs; load average at start "
            f"{load:.2f})",
            f"- Python {platform.python_version()} ({platform.python_implementation()}), numpy {np.__version__}, "
            f"scipy {scipy.__version__}, {blas.get('name', '?')} {blas.get('version', '')}",
            f"- BLAS threads: OPENBLAS_NUM_THREADS = {os.environ.get('OPENBLAS_NUM_THREADS')}, "
            f"OMP_NUM_THREADS = {os.environ.get('OMP_NUM_THREADS')}",
            f"- {platform.platform()}"]


def fmt_time(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "-"
    return f"{seconds * 1e3:.3g} ms" if seconds >= 1e-3 else f"{seconds * 1e6:.3g} us"


def fmt_error(value: float) -> str:
    return "-" if not math.isfinite(value) else ("0" if value == 0.0 else f"{value:.1e}")


def plot(rows: list[Row], choices: list[AutoChoice], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    families = list(dict.fromkeys(r.family for r in rows))
    fig, axes = plt.subplots(2, 3, figsize=(17, 10.5))
    colours = {"closed_form": "black", "polynomial": "tab:blue", "discretised": "tab:orange",
               "quasi-static": "tab:gray", "relaxation": "tab:green", "transient": "tab:orange",
               "transient pair": "tab:brown"}
    markers = "osD^vP*X"
    for ax, family in zip(axes.flat, families, strict=False):
        cases = list(dict.fromkeys(r.case for r in rows if r.family == family))
        for ci, case in enumerate(cases):
            case_rows = [r for r in rows if r.family == family and r.case == case and math.isfinite(r.error)]
            groups = {}
            for r in case_rows:
                groups.setdefault((r.method, tuple(r.options)), []).append(r)
            for (method, keys), group in groups.items():
                hollow = "order" in keys
                ax.plot([r.time for r in group], [max(r.error, ERROR_FLOOR) for r in group],
                        marker=markers[ci % len(markers)], ls=":" if hollow else "-", lw=0.8,
                        color=colours.get(method, "tab:purple"), mfc="none" if hollow else colours.get(method),
                        alpha=0.8, ms=5)
            front = pareto_front(case_rows)
            ax.step([r.time for r in front], [max(r.error, ERROR_FLOOR) for r in front], where="post", color="0.6",
                    lw=2.5, alpha=0.35, zorder=0)
            for choice in (c for c in choices if c.family == family and c.case == case):
                ax.plot(choice.time, max(choice.error, ERROR_FLOOR), marker="*", color="red", ms=13, mec="darkred",
                        zorder=5)
                ax.annotate(f"{choice.tolerance:.0e}", (choice.time, max(choice.error, ERROR_FLOOR)), fontsize=7,
                            color="darkred", xytext=(4, 2 + 7 * TOLERANCES.index(choice.tolerance)),
                            textcoords="offset points")
        for tolerance in TOLERANCES:
            ax.axhline(tolerance, color="red", lw=0.5, ls="--", alpha=0.4)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{family} ({len(cases)} case{'s' if len(cases) > 1 else ''})", fontsize=10)
        ax.set_xlabel("time per step [s]" if family == "instationary" else "time per solve [s]")
        ax.set_ylabel("max |T' - T'_ref| / (mu N')" if family == "instationary" else "relative error of T' and p0")
        ax.grid(True, which="major", alpha=0.3)
        legend = [plt.Line2D([], [], color=colours.get(m, "tab:purple"), marker="o", ls="-", label=m.replace("_", " "))
                  for m in dict.fromkeys(r.method for r in rows if r.family == family)]
        legend += [plt.Line2D([], [], color="k", marker=markers[i % len(markers)], ls="none", mfc="none",
                              label=c[:38]) for i, c in enumerate(cases)]
        legend += [plt.Line2D([], [], color="red", marker="*", ls="none", ms=11, label="auto at tolerance"),
                   plt.Line2D([], [], color="0.6", lw=2.5, alpha=0.4, label="Pareto front (per case)")]
        ax.legend(handles=legend, fontsize=6.5, loc="best")
    for ax in list(axes.flat)[len(families):]:
        ax.axis("off")
    fig.suptitle("rollcontact: error vs time per setting (log-log); dotted/hollow: explicit polynomial orders",
                 fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fmu_overhead_lines(rows: list[Row], empty: float) -> list[str]:
    """Headline lines: each steady setting's FMU step over its solve() and the difference, per method (the FMU's
    own share: pythonfmu's step, the model building the scene and its outputs, fmpy's calls)."""
    lines = []
    for method in ("closed_form", "polynomial", "discretised"):
        pairs = [(r.fmu_time, r.time) for r in rows if r.method == method and r.family != "instationary"
                 and math.isfinite(r.fmu_time) and math.isfinite(r.time)]
        if not pairs:
            continue
        ratios = [f / t for f, t in pairs]
        extra = statistics.median(f - t for f, t in pairs)
        lines.append(f"- FMU step over solve() of the same setting, {method.replace('_', ' ')}: median "
                     f"{statistics.median(ratios):.3g}x (range {min(ratios):.3g}-{max(ratios):.3g}x over {len(pairs)} "
                     f"settings); the FMU adds a median {fmt_time(extra)} per step"
                     + (f" (the empty FMU step: {fmt_time(empty)})" if math.isfinite(empty) else ""))
    return lines


TENS_OF_US = 100e-6  # s: "tens of microseconds"
CONTACT_CARTER = 2e-3  # s: CONTACT on a 100-element 2D Carter case, as the brief quotes it for these machines
CONTACT_FALLING = (7e-3, 20e-3)  # s: CONTACT on a falling-friction case, likewise


def auto_times(choices: list[AutoChoice], rows: list[Row], family: str, tolerance: float = 1e-3) -> list[float]:
    """auto's times per solve at ``tolerance`` on the family's one-patch cases (no setting found more patches)
    where it met it."""
    one_patch = ({r.case for r in rows if r.family == family}
                 - {r.case for r in rows if r.family == family and r.patches > 1})
    return [c.time for c in choices if c.family == family and c.case in one_patch and c.tolerance == tolerance
            and c.error <= tolerance and math.isfinite(c.time)]


def aims_lines(rows: list[Row], choices: list[AutoChoice], fmu: list) -> list[str]:
    """The brief's aims against this run's figures: a table of aim, measurement and verdict."""

    def span(values: list[float]) -> str:
        return (f"median {fmt_time(statistics.median(values))}, max {fmt_time(max(values))} over {len(values)} "
                "case(s)")

    out = []
    closed = [ratio for label, _, ratio, _, _ in fmu if label.startswith("closed form")]
    if closed:
        out.append(("closed-form FMU step within 1.5x an empty pythonfmu step", f"{closed[0]:.2f}x",
                    closed[0] <= 1.5))
    for family, what in (("corrugation", "corrugated"), ("velocity-dependent friction", "falling-friction")):
        values = auto_times(choices, rows, family)
        if values:
            out.append((f"{what} solves in tens of microseconds at 0.1 % (`solve(scene, tolerance=1e-3)`, one "
                        "patch)", span(values), max(values) < TENS_OF_US))
    ratios = equal_accuracy_ratios([r for r in rows if r.family != "instationary"], 1e-3, False)
    if ratios:
        median = statistics.median(q.ratio for q in ratios)
        bounds = sum(q.lower_bound for q in ratios)
        out.append(("the polynomial method 1000x faster than the discretised solver at equal accuracy (1e-3)",
                    f"median {median:.3g}x over {len(ratios)} cases ({bounds} lower bounds)", median >= 1000.0))
    for family, contact, figure in (("Hertz/Carter", f"~{fmt_time(CONTACT_CARTER)} on a 100-element Carter case",
                                     CONTACT_CARTER),
                                    ("velocity-dependent friction", f"{fmt_time(CONTACT_FALLING[0])}-"
                                     f"{fmt_time(CONTACT_FALLING[1])} on a falling-friction case",
                                     CONTACT_FALLING[0])):
        chosen = auto_times(choices, rows, family, 1e-2)
        like = [r for r in rows if r.family == family and r.patches == 1 and r.method == "discretised"
                and r.options == {"elements": 100} and math.isfinite(r.time)]
        if chosen:
            measured = (f"auto at 1e-2 (CONTACT's ~1 % errors): {span(chosen)}, {figure / max(chosen):.3g}x faster at "
                        "worst")
            if like:
                measured += (f"; like for like, discretised n = 100: {span([r.time for r in like])}, error up to "
                             f"{fmt_error(max(r.error for r in like))}")
            out.append((f"faster than CONTACT's {contact} at ~1 % (quoted, not run here)", measured,
                        max(chosen) < figure))
    if not out:
        return []
    return ["## Against the brief's aims", "",
            "The aims of the project brief, each against this run's figures (CONTACT's times are the brief's, for "
            "these machines; CONTACT itself is not run).  Zero crashes over the input domain is the property "
            "tests' (`tests/test_properties.py`, `tests/test_fmu_properties.py`), not this study's.", "",
            "| aim | this run | met |", "|---|---|---|",
            *(f"| {aim} | {measured} | {'yes' if met else '**no**'} |" for aim, measured, met in out), ""]


def auto_summary(choices: list[AutoChoice]) -> list[str]:
    """Headline lines: how often auto met t, and its cost over the cheapest measured setting that met t."""
    met = [c for c in choices if c.error <= c.tolerance]
    reachable = [c for c in choices if not math.isnan(c.cheapest_time)]
    ratios = [c.paired for c in reachable if c.error <= c.tolerance]
    lines = [f"- auto met the requested tolerance in {len(met)} of {len(choices)} cases (t = "
             f"{', '.join(f'{t:.0e}' for t in TOLERANCES)}); some setting measured met it in {len(reachable)}"]
    certified = [c.certified_paired for c in choices if not math.isnan(c.certified_paired)]
    for what, values in (("the cheapest measured setting meeting t, where auto met t", ratios),
                         ("the cheapest measured setting whose a-priori error bound meets t (what can be known "
                          "before solving)", certified)):
        if values:
            lines.append(f"- auto's time over {what} (timed alternately, {PAIRED_ROUNDS} rounds): median "
                         f"{statistics.median(values):.2f}x, max {max(values):.2f}x; within {LOWEST_COST_SLACK}x "
                         f"(timing noise and the choice itself) in {sum(r <= LOWEST_COST_SLACK for r in values)} of "
                         f"{len(values)}")
    return lines


def report(config, rows, choices, references, inst_refs, fmu, elapsed, load, path: Path) -> None:
    lines = ["# Speed-accuracy Pareto study" + (" (quick smoke test)" if config.quick else ""), "",
             f"Generated {datetime.datetime.now().isoformat(timespec='seconds')} by "
             f"`.venv/bin/python benchmarks/pareto.py{' --quick' if config.quick else ''}` in {elapsed:.0f} s "
             "(figure: `pareto.png`).  Method and definitions: the docstring of `benchmarks/pareto.py`.", "",
             "## Machine", "", *machine(load), "",
             "Timings on this shared machine are noisy (other jobs run alongside): ratios measured in the same run "
             "are meaningful, absolute times only roughly.", ""]
    # headline ratios
    lines += ["## Headline ratios (same run)", ""]
    closed = statistics.median([r.time for r in rows if r.method == "closed_form"])
    ratio_lines, ratio_table = equal_accuracy_lines(rows)
    lines += ratio_lines
    if fmu:
        for label, _, ratio, _, _ in fmu[1:]:
            lines.append(f"- FMU step / empty pythonfmu FMU step, {label}: {ratio:.3g}x")
    lines += fmu_overhead_lines(rows, fmu[0][1] * 1e-6 if fmu else math.nan)
    lines += auto_summary(choices)
    lines.append(f"- Each method vs the closed form (solve() on Hertz/Carter, {fmt_time(closed)}):")
    for title, selector in (
            ("polynomial, corrugation (the setting auto chose at 1e-3, run directly)",
             lambda r: r.family == "corrugation" and r.method == "polynomial" and 1e-3 in r.auto),
            ("polynomial, velocity-dependent friction, one patch (the setting auto chose at 1e-3, run directly)",
             lambda r: r.family.startswith("velocity") and r.method == "polynomial" and 1e-3 in r.auto
             and r.patches == 1),
            ("polynomial, velocity-dependent friction, split contact (the setting auto chose at 1e-3, run directly)",
             lambda r: r.family.startswith("velocity") and r.method == "polynomial" and 1e-3 in r.auto
             and r.patches > 1),
            ("discretised n = 200, Coulomb", lambda r: r.method == "discretised" and r.options == {"elements": 200}
             and r.family != "velocity-dependent friction"),
            ("discretised n = 200, velocity-dependent, one patch", lambda r: r.method == "discretised"
             and r.options == {"elements": 200} and r.family == "velocity-dependent friction" and r.patches == 1),
            ("discretised n = 200, velocity-dependent, split contact", lambda r: r.method == "discretised"
             and r.options == {"elements": 200} and r.family == "velocity-dependent friction" and r.patches > 1),
            ("quasi-static step", lambda r: r.method == "quasi-static"),
            ("relaxation step", lambda r: r.method == "relaxation"),
            ("transient step, n = 100", lambda r: r.method == "transient" and r.options == {"elements": 100})):
        times = [r.time for r in rows if selector(r)]
        if times:
            median = statistics.median(times)
            lines.append(f"  - {title}: {median / closed:.3g}x (median {fmt_time(median)} over {len(times)} "
                         "case(s))")
    lines += ratio_table
    lines += aims_lines(rows, choices, fmu)
    # references
    lines += ["## References", "", "| family | case | reference | cross-check |", "|---|---|---|---|"]
    for (family, case), ref in references.items():
        lines.append(f"| {family} | {case} | {ref.how} | {ref.check or '-'} |")
    for case, how, check in inst_refs:
        lines.append(f"| instationary | {case} | {how} | {check} |")
    lines.append("")
    # auto
    lines += ["## auto at each requested tolerance", "",
              "auto takes the cheapest setting (by the cost model of `api.py`) whose predicted error bound meets t.  "
              "Steady: `solve(scene, tolerance=t)`; instationary: the FMU's stepping model with `transient = 1` "
              "(auto) and `tolerance = t` (it switches between quasi-static Carter, the relaxation lag while the "
              "lag's bound for the creep swing seen over the last 8 relaxation lengths meets t, and the discretised "
              "transient, a pair of nested grids extrapolated, where it does not; the lag's 'bound' below is the "
              "largest over the measured cycle).  "
              "'cheapest measured' is the fastest measured setting whose error is <= t (by measured time, so "
              "noise and lucky cancellations count).  'x cheapest': auto's time over it, timed again alternately "
              f"with it ({PAIRED_ROUNDS} rounds, the median ratio: the machine's speed drifts over the minutes "
              "between the rows); 'unpaired': the ratio of the times in the table, with the time of auto's setting "
              "run directly over it in brackets (steady: the rest is the choice itself; instationary: where every "
              "measured step ran one model, the rest is the model's overhead).  'cheapest certified': the fastest "
              "measured setting whose a-priori error bound (the 'bound' column below) meets t, the best choice "
              "possible without hindsight of the errors; 'x certified': auto's time over it, timed alternately "
              "likewise.  'FMU step': the contact FMU with `method = 0` (auto) and `tolerance = t` stepped through "
              "fmpy on the same scene (steady cases; the instationary times are already steps of the FMU's model).",
              "",
              "| family | case | t | auto's choice | error | estimate | meets t | time | FMU step | cheapest measured "
              "meeting t | x cheapest | unpaired | cheapest certified | x certified |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in choices:
        meets = "yes" if c.error <= c.tolerance else "**no**"
        ratio = "-" if math.isnan(c.cheapest_time) else f"{c.time / c.cheapest_time:.2f}" + (
            "" if math.isnan(c.chosen_time) else f" ({c.chosen_time / c.cheapest_time:.2f})")
        paired = "-" if math.isnan(c.paired) else f"{c.paired:.2f}"
        lines.append(f"| {c.family} | {c.case} | {c.tolerance:.0e} | {c.label} | {fmt_error(c.error)} | "
                     f"{fmt_error(c.estimate)} | {meets} | {fmt_time(c.time)} | {fmt_time(c.fmu_time)} | "
                     f"{c.cheapest or 'none'} | {paired} | "
                     f"{ratio} | {c.certified or 'none'} | "
                     f"{'-' if math.isnan(c.certified_paired) else f'{c.certified_paired:.2f}'} |")
    lines.append("")
    # per family tables
    lines += ["## Every setting", "",
              "error: the larger of the T' and p0 errors (instationary: T' in units of mu N').  time: per solve() "
              "(instationary: per step of the FMU's model).  FMU step: the contact FMU running the same setting on "
              "the same scene, per fmpy step (set 3 inputs, doStep, get 11 outputs; `common.steady_step_time`): "
              "'-' where no FMU parameter selects the setting (the slip iteration's nodes, the extrapolated "
              "discretised pairs) and for the instationary rows, whose times are already model steps.  model: the "
              "cost model of `api.py` [s] and the predicted error bound; 'front': on the case's Pareto front; "
              "'auto': the tolerances at which auto chose this setting.", ""]
    for family in dict.fromkeys(r.family for r in rows):
        lines += [f"### {family}", "",
                  "| case | setting | error T' | error p0 | error | time | FMU step | model cost | bound | front "
                  "| auto |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for case in dict.fromkeys(r.case for r in rows if r.family == family):
            case_rows = [r for r in rows if r.family == family and r.case == case]
            front = {id(r) for r in pareto_front(case_rows)}
            for r in case_rows:
                lines.append(f"| {case} | {r.label}{' (' + r.note + ')' if r.note else ''} | "
                             f"{fmt_error(r.error_force)} | {fmt_error(r.error_pressure)} | {fmt_error(r.error)} | "
                             f"{fmt_time(r.time)} | {fmt_time(r.fmu_time)} | {fmt_time(r.model_cost)} | "
                             f"{fmt_error(r.bound)} | "
                             f"{'x' if id(r) in front else ''} | {', '.join(f'{t:.0e}' for t in r.auto)} |")
        lines.append("")
    # model checks
    steady = [r for r in rows if r.family != "instationary"]
    rho, agree, pairs = rank_agreement(steady)
    lines += ["## Cost and error models of auto (`src/rollcontact/api.py`) against this run", "",
              f"- Cost model vs measured time: Spearman rank correlation {rho:.3f} over {len(steady)} settings; "
              f"same-case pairs whose times differ by > 30 % ordered alike: {agree:.0%} of {pairs}.",
              "- Fitted constants (least squares on relative residuals; update `api.py` when the ranking drifts):",
              "", "| constant | api.py | fitted here |", "|---|---|---|"]
    lines += [f"| {name} | {now} | {fitted} |" for name, now, fitted in fit_costs(steady)]
    violations = [r for r in rows if math.isfinite(r.bound) and math.isfinite(r.error) and r.error > r.bound]
    ratios = [r.bound / max(envelope(steady, r), 1e-15) for r in steady
              if math.isfinite(r.bound) and math.isfinite(r.error) and r.method != "closed_form"
              and "tolerance" not in r.options]
    lines += ["", f"- Error bounds violated (error > bound, every family): {len(violations)}"
              + "".join(f"; {r.case}, {r.label}: {r.error:.2e} > {r.bound:.2e}" for r in violations),
              f"- How pessimistic (bound over the converged error, discretised and slip-node settings): median "
              f"{statistics.median(ratios):.3g}, max {max(ratios):.3g}" if ratios else "", ""]
    if fmu:
        lines += ["## FMU step (fmpy, one step = setReal(3) + doStep + getReal(10) + getInteger(1))", "",
                  "| case | median us/step | x empty FMU | discarded | method_used |", "|---|---|---|---|---|"]
        lines += [f"| {label} | {us:.1f} | {ratio:.2f} | {discards} | {sorted(used)} |"
                  for label, us, ratio, discards, used in fmu]
        lines.append("")
    path.write_text("\n".join(lines))


# ------------------------------------------------------------------------------------------------------- main
def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smoke test (< 60 s)")
    parser.add_argument("--no-fmu", action="store_true", help="skip the FMU step timing")
    args = parser.parse_args(argv)
    config = QUICK if args.quick else FULL
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="pareto_fmu_") as tmp:
        bench = None
        if not args.no_fmu:
            from build_fmu import build

            print("building the FMUs", flush=True)
            bench = FmuBench(*common.build_and_extract(Path(tmp), build), Path(tmp))
        rows, choices, references = [], [], {}
        for family, cases in steady_cases(config).items():
            for label, scene in cases:
                print(f"{family}: {label}", flush=True)
                case_rows, case_choices, ref = measure_case(family, label, scene, config, bench)
                rows += case_rows
                choices += case_choices
                references[(family, label)] = ref
        print("instationary", flush=True)
        inst_rows, inst_choices, inst_refs = instationary_study(config)
        rows += inst_rows
        choices += inst_choices
        fmu = []
        if bench is not None:
            print("FMU steps", flush=True)
            fmu = fmu_study(config, bench)
    RESULTS.mkdir(parents=True, exist_ok=True)
    plot(rows, choices, RESULTS / "pareto.png")
    report(config, rows, choices, references, inst_refs, fmu, time.perf_counter() - start, load,
           RESULTS / "pareto.md")
    print(f"wrote {RESULTS / 'pareto.md'} and {RESULTS / 'pareto.png'} in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
