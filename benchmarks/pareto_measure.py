"""The Pareto study's measurements: every setting and auto on each steady case, the instationary study, FMU steps.

The method: the docstring of ``benchmarks/pareto.py``.
"""

from __future__ import annotations

import math
import os
import statistics
import tempfile
from dataclasses import dataclass
from pathlib import Path

import common
import numpy as np
from instationary_case import (
    A_I,
    LIMIT,
    STEPS_PER_CYCLE,
    instationary_stepper,
    lag_bounds,
    pair_stepper,
    run_instationary,
)
from pareto_cases import (
    TOLERANCES,
    AutoChoice,
    Config,
    Reference,
    Row,
    fmt_time,
    patch_count,
    setting_label,
    steady_reference,
    steady_settings,
    worst_placement_errors,
)

import rollcontact as rc
from rollcontact.line.methods.common import friction_sharpness
from rollcontact.stepping.line.parameters import INSTATIONARY_CODES
from rollcontact.stepping.line.transient import transient_model_error, transient_setting

# ------------------------------------------------------------------------------------------------------ timing
BATCH_SECONDS = 2e-3  # s: the least duration of one timing sample (timeit-style batches of calls)


def solve_time(function, budget: float) -> float:
    """Median time per call [s] of ``function`` as the study times a solve: after a warm-up call, samples of
    batches of calls lasting at least ~2 ms (:data:`BATCH_SECONDS`), at least 3 and up to 200 within ``budget`` [s]
    (:func:`common.median_time`)."""
    return common.median_time(function, min_repeats=3, min_seconds=budget, warmups=1, batch_seconds=BATCH_SECONDS,
                              max_repeats=200)


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


# ------------------------------------------------------------------------------------------------- steady study
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
    if method == "polynomial" and set(options) == {"truncation"}:
        # the FMU's tolerance picks the loosest truncation <= t: t itself for TRUNCATIONS
        return {"method": 2, "tolerance": options["truncation"]}
    if method == "polynomial" and set(options) == {"order"}:
        return {"method": 2, "polynomial_order": options["order"]}
    if method == "discretised" and set(options) == {"elements"}:
        return {"method": 3, "elements": options["elements"]}
    return None


def fmu_step_time(fmu: FmuBench | None, scene_file: str, scene: rc.Scene, parameters: dict | None,
                  config: Config) -> float:
    """Seconds per fmpy step of a fresh contact FMU reading ``scene_file`` with ``parameters``, its axis at the
    scene's and its inputs the scene's load (over :data:`common.CONTACT_WIDTH`), creep and speed
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
                      "contact_width": common.CONTACT_WIDTH, **parameters},
        (scene.normal_load_per_length * common.CONTACT_WIDTH, scene.creep), scene.rolling_speed, config.budget,
        before_step=common.influence_cache_clear() if parameters["method"] in (0, 3) else None)
    return math.nan if discards else us * 1e-6


def measure_case(family: str, label: str, scene: rc.Scene, config: Config,
                 fmu: FmuBench | None = None) -> tuple[list[Row], list[AutoChoice], Reference]:
    """Every setting of :func:`pareto_cases.steady_settings` and auto at each of :data:`pareto_cases.TOLERANCES` on
    one steady case: its rows, auto's choices and the case's reference."""
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
                        sharpness=0.0 if scene.friction.is_constant else friction_sharpness(scene),
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


# --------------------------------------------------------------------------------------------- instationary study
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
    """Every instationary setting and auto at each tolerance on each signal of ``config``: the rows, auto's choices
    and (case, reference, cross-check) per signal."""
    rows, choices, references = [], [], []
    limit = LIMIT
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
                                 "order, benchmarks/calibrate_transient_pairs.py) in the FMU model",
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


# ---------------------------------------------------------------------------------------------------- FMU steps
def fmu_study(config: Config, fmu: FmuBench) -> list[tuple[str, float, float, int, set]]:
    """(label, median us/step, ratio to the empty FMU, discarded steps, method_used codes) per case."""
    corrugation, case = common.FMU_CORRUGATION, common.Case
    empty, contact = fmu.empty, fmu.contact
    cases = [case("empty pythonfmu FMU", empty, {}, 200, 1.0),
             case("closed form (method 1)", contact, {"method": 1}, 200, 20.0),
             case("polynomial, corrugation 40 mm / 20 um (method 2, table off)", contact,
                  {"method": 2, "table": 1, **corrugation}, 10, 1.0),
             case("auto, corrugation, tolerance 1e-3 (method 0, table off)", contact,
                  {"method": 0, "tolerance": 1e-3, "table": 1, **corrugation}, 10, 1.0),
             case("corrugation, certified table (table on, tolerance 1e-3)", contact,
                  {"method": 0, "tolerance": 1e-3, "table": 2, **corrugation}, 200, 1.0),
             case("falling friction, auto (method 0, table off)", contact,
                  {"method": 0, "friction_law": 1, "table": 1}, 2, 20.0),
             case("falling friction, auto, tolerance 1e-3 (method 0, table off)", contact,
                  {"method": 0, "friction_law": 1, "tolerance": 1e-3, "table": 1}, 2, 20.0),
             case("falling friction, certified table (table on, tolerance 1e-3)", contact,
                  {"method": 0, "friction_law": 1, "tolerance": 1e-3, "table": 2}, 200, 20.0),
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


