"""A fixed, varying input signal through the RollingContact3D FMUs, for every level, against recorded outputs.

``tests/fmu/data/fmu_fingerprint_3d.json`` holds every output of every step of each case as ``repr`` strings, with the
outputs' names, written by ``python tests/fmu/test_fmu_fingerprint_3d.py --record``.  The cases drive
``RollingContact3D`` and ``RollingContact3D_8`` (FMI 2.0, ``build_fmu.py --contacts 8``; eight contacts of different
curvatures and inputs, one of them lifting off for a step) through fmpy's ``FMU2Slave`` with load, the three
creepages and speed changing every step: every level (``method`` auto, linear, fastsim, strips, discretised), with
and without spin, both ``jacobian`` modes, a falling-friction rail condition and a tolerance; a few cases run the
FMI 3.0 single-contact FMU (fmpy's ``FMU3Slave``) too, against the FMI 2.0 FMU's run bit for bit and against the
same record.  A refactoring must leave them unchanged.

Tolerances, relative to each output's largest magnitude over the case (measured by running every case under other
OpenBLAS kernels, ``OPENBLAS_CORETYPE`` Sandybridge, Nehalem and Prescott, and numpy without its AVX2 targets,
``NPY_DISABLE_CPU_FEATURES=X86_V3``):

* no path is bit for bit across kernels: even the linear level, whose steps are float arithmetic in Python, takes
  Kalker's coefficients at each ellipse's a/b from a cubic spline that scipy solves through LAPACK, and another
  kernel moves some of them in the last bit (outputs by up to 3e-16 of their scale);
* 1e-12 on the levels of closed forms and numpy array arithmetic (linear, FASTSIM, the strips, and ``auto``, the
  falling-friction and the ``tolerance`` cases that take only those): another CPU may take another BLAS or SIMD
  kernel with another rounding (measured: up to 7e-16);
* 1e-7 on every case that takes the discretised level in a step: its semismooth Newton with FFT-preconditioned GMRES
  stops at an iteration tolerance (1e-8 of max mu p), so another kernel's rounding may end the iteration a step
  earlier or later (one Newton step more moves the forces by up to 4e-10 of mu Fn on these scenes; measured under
  the other kernels: up to 1e-15);
* ``jacobian`` = 1 (forward differences of the step's level, increments of 1e-4 of each creepage's saturation value)
  divides a force's rounding by the increment: its derivative outputs get the case's tolerance times 1e4 (measured:
  up to 6e-11).

On one machine every case repeats bit for bit from run to run (and with two BLAS threads); the FMI 3.0 twins equal
their FMI 2.0 runs bit for bit.
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path
from typing import NamedTuple

import pytest

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as tests/conftest.py, for the --record run

import numpy as np  # noqa: E402

DATA = Path(__file__).resolve().parent / "data" / "fmu_fingerprint_3d.json"
H = 1e-3
INPUTS = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")
CURVATURES = ((1.087, 1.667), (2.5, 1.2), (0.9, 4.0), (1.1, 0.5), (1.0, 8.0), (3.0, 1.0), (1.3, 1.3), (0.8, 2.2))
"""A, B [1/m] of the eight contacts: a/b from about 0.6 to 4 (the first is near the FMU's default)."""
LIFTED = (7, 2)
"""(contact, step) without load: the eighth contact lifts off at step 2 (an all-zero output row, ``method_used`` 0)."""

KERNEL, ITERATED = 1e-12, 1e-7
DIFFERENCE_GAIN = 1e4
"""A forward difference's rounding over a force's: 1 / the increment (1e-4 of the saturation creepage)."""
LINEAR, FASTSIM, STRIPS, DISCRETISED = 1, 2, 3, 4  # the FMU's Method3D codes (0 auto)
DRY = 1  # RailCondition: Polach's dry rail, a falling friction law
CHEAP_BUDGET = 0.12
"""``step_budget`` [s] that keeps the discretised level on 16 x 16 elements: its capped work fits, that of 24 x 24
does not (:func:`rollcontact.elliptic.methods.discretised.bounded_cost`)."""
PAIR_BUDGET = 0.4
"""``step_budget`` [s] whose most accurate fitting setting of the discretised level is the 32/16 Richardson pair."""


class Case(NamedTuple):
    contacts: int
    spin: bool
    steps: int
    tier: float
    parameters: dict


CASES = {
    # one contact, every level with and without spin
    "auto_spin": Case(1, True, 16, KERNEL, {}),
    "auto_no_spin": Case(1, False, 16, KERNEL, {}),
    "linear_spin": Case(1, True, 16, KERNEL, {"method": LINEAR}),
    "linear_no_spin": Case(1, False, 16, KERNEL, {"method": LINEAR}),
    "fastsim_spin": Case(1, True, 16, KERNEL, {"method": FASTSIM}),
    "fastsim_no_spin": Case(1, False, 16, KERNEL, {"method": FASTSIM}),
    "strips_spin": Case(1, True, 16, KERNEL, {"method": STRIPS}),
    "strips_no_spin": Case(1, False, 16, KERNEL, {"method": STRIPS}),
    "discretised_spin": Case(1, True, 4, ITERATED, {"method": DISCRETISED, "step_budget": CHEAP_BUDGET}),
    "discretised_no_spin": Case(1, False, 4, ITERATED, {"method": DISCRETISED, "step_budget": CHEAP_BUDGET}),
    "discretised_spin_pair": Case(1, True, 4, ITERATED, {"method": DISCRETISED, "step_budget": PAIR_BUDGET}),
    # jacobian = 1: forward differences of the step's level
    "auto_spin_difference": Case(1, True, 16, KERNEL, {"jacobian": 1}),
    "linear_spin_difference": Case(1, True, 16, KERNEL, {"method": LINEAR, "jacobian": 1}),
    "fastsim_spin_difference": Case(1, True, 16, KERNEL, {"method": FASTSIM, "jacobian": 1}),
    "strips_spin_difference": Case(1, True, 16, KERNEL, {"method": STRIPS, "jacobian": 1}),
    "strips_no_spin_difference": Case(1, False, 16, KERNEL, {"method": STRIPS, "jacobian": 1}),
    "discretised_spin_difference": Case(1, True, 4, ITERATED,
                                        {"method": DISCRETISED, "step_budget": 4 * CHEAP_BUDGET, "jacobian": 1}),
    # falling friction (a rail condition) and a tolerance
    "dry_auto_spin": Case(1, True, 16, ITERATED, {"rail_condition": DRY}),
    "dry_auto_no_spin": Case(1, False, 16, KERNEL, {"rail_condition": DRY}),
    "dry_strips_no_spin": Case(1, False, 16, KERNEL, {"rail_condition": DRY, "method": STRIPS}),
    "tolerance_auto_spin": Case(1, True, 16, ITERATED, {"tolerance": 0.05}),
    "tolerance_auto_no_spin": Case(1, False, 16, KERNEL, {"tolerance": 0.05}),
    "tolerance_strips_spin": Case(1, True, 16, KERNEL, {"method": STRIPS, "tolerance": 0.02}),
    # eight contacts of different curvatures and inputs
    "8_auto_spin": Case(8, True, 8, KERNEL, {}),
    "8_auto_no_spin": Case(8, False, 8, KERNEL, {}),
    "8_linear_spin": Case(8, True, 8, KERNEL, {"method": LINEAR}),
    "8_linear_no_spin": Case(8, False, 8, KERNEL, {"method": LINEAR}),
    "8_fastsim_spin": Case(8, True, 8, KERNEL, {"method": FASTSIM}),
    "8_fastsim_no_spin": Case(8, False, 8, KERNEL, {"method": FASTSIM}),
    "8_strips_spin": Case(8, True, 8, KERNEL, {"method": STRIPS}),
    "8_strips_no_spin": Case(8, False, 8, KERNEL, {"method": STRIPS}),
    "8_discretised_spin": Case(8, True, 4, ITERATED, {"method": DISCRETISED, "step_budget": CHEAP_BUDGET}),
    "8_discretised_no_spin": Case(8, False, 4, ITERATED, {"method": DISCRETISED, "step_budget": CHEAP_BUDGET}),
    "8_auto_spin_difference": Case(8, True, 8, KERNEL, {"jacobian": 1}),
    "8_strips_spin_difference": Case(8, True, 8, KERNEL, {"method": STRIPS, "jacobian": 1}),
    "8_dry_auto_spin": Case(8, True, 4, ITERATED, {"rail_condition": DRY}),
    "8_tolerance_auto_spin": Case(8, True, 4, ITERATED, {"tolerance": 0.05}),
}
"""name: (contacts, spin, steps, tolerance tier (module docstring), parameters by name)."""

FMI3_TWINS = ("linear_spin", "strips_spin_difference", "dry_auto_no_spin", "tolerance_auto_no_spin",
              "discretised_spin")
"""Cases the FMI 3.0 RollingContact3D runs too: one per family of paths, a few seconds in all."""


def named(name: str, k: int, contacts: int) -> str:
    """The FMI 2.0 name of ``name`` for contact ``k`` (from 1): plain with one contact, ``name[k]`` with several."""
    return name if contacts == 1 else f"{name}[{k}]"


def signal(n: int, k: int, spin: bool) -> tuple[float, float, float, float, float]:
    """Load [N], longitudinal and lateral creepage [1], spin [1/m] and speed [m/s] of contact ``k`` (from 0) at step
    ``n``: each contact its own phase and load, the creepages through the saturation value (some 2e-3) and back."""
    if (k, n) == LIFTED:
        return 0.0, 0.0, 0.0, 0.0, 30.0
    load = 7e4 * (1.0 + 0.05 * k) * (1.0 + 0.3 * math.sin(0.7 * n + k))
    xi = 3e-3 * math.sin(0.9 * n + 0.4 * k) + 1e-4 * n
    eta = -2e-3 * math.cos(0.6 * n + 0.8 * k)
    phi = 0.4 * math.sin(0.5 * n - k) if spin else 0.0
    speed = 30.0 + 3.0 * math.cos(0.3 * n + k)
    return load, xi, eta, phi, speed


def parameters_of(case: Case) -> dict:
    """The case's parameters with each contact's curvatures."""
    curvatures = {named(name, k, case.contacts): CURVATURES[k - 1][i] for k in range(1, case.contacts + 1)
                  for i, name in enumerate(("curvature_longitudinal", "curvature_lateral"))}
    return {**curvatures, **case.parameters}


def run(unzipped, description, name: str, case: Case) -> tuple[list[str], list[list[float]]]:
    """The output names and, step by step, every output of the FMI 2.0 FMU (an integer as a float)."""
    from fmpy.fmi2 import FMU2Slave

    variables = {v.name: v for v in description.modelVariables}
    fmu = FMU2Slave(guid=description.guid, unzipDirectory=str(unzipped),
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName=name)
    fmu.instantiate()
    outputs = [v for v in description.modelVariables if v.causality == "output"]
    rows = []
    try:
        for key, value in parameters_of(case).items():
            v = variables[key]
            (fmu.setReal if v.type == "Real" else fmu.setInteger)([v.valueReference], [value])
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        inputs = [variables[named(n, k, case.contacts)].valueReference for k in range(1, case.contacts + 1)
                  for n in INPUTS]
        reals = [v.valueReference for v in outputs if v.type == "Real"]
        integers = [v.valueReference for v in outputs if v.type != "Real"]
        for n in range(case.steps):
            fmu.setReal(inputs, [x for k in range(case.contacts) for x in signal(n, k, case.spin)])
            fmu.doStep(n * H, H)
            values = dict(zip(reals, fmu.getReal(reals), strict=True))
            values.update(zip(integers, (float(i) for i in fmu.getInteger(integers)), strict=True))
            rows.append([float(values[v.valueReference]) for v in outputs])
    finally:
        fmu.terminate()
        fmu.freeInstance()
    return [v.name for v in outputs], rows


def run3(unzipped, description, name: str, case: Case, names: list[str]) -> list[list[float]]:
    """The outputs ``names`` of the single-contact FMI 3.0 FMU, step by step (an enumeration as a float)."""
    from fmpy.fmi3 import FMU3Slave

    assert case.contacts == 1, f"{name}: the FMI 3.0 twins are single-contact cases"
    variables = {v.name: v for v in description.modelVariables}
    fmu = FMU3Slave(guid=description.guid, unzipDirectory=str(unzipped),
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName=name)
    fmu.instantiate()
    rows = []
    try:
        for key, value in parameters_of(case).items():
            v = variables[key]
            set_ = {"Float64": fmu.setFloat64, "Int32": fmu.setInt32}.get(v.type, fmu.setInt64)  # Enumeration: Int64
            set_([v.valueReference], [value])
        fmu.enterInitializationMode(startTime=0.0)
        fmu.exitInitializationMode()
        inputs = [variables[n].valueReference for n in INPUTS]
        getters = [({"Float64": fmu.getFloat64, "Int32": fmu.getInt32}.get(variables[n].type, fmu.getInt64),
                    variables[n].valueReference) for n in names]
        for n in range(case.steps):
            fmu.setFloat64(inputs, list(signal(n, 0, case.spin)))
            fmu.doStep(n * H, H)
            rows.append([float(get([vr])[0]) for get, vr in getters])
    finally:
        fmu.terminate()
        fmu.freeInstance()
    return rows


def tolerances(case: Case, names: list[str]) -> np.ndarray:
    """Each output's tolerance relative to its scale: the case's tier, times the difference gain for the derivative
    outputs of ``jacobian`` = 1 (module docstring)."""
    difference = case.parameters.get("jacobian") == 1
    return np.array([case.tier * (DIFFERENCE_GAIN if difference and n.startswith("d") else 1.0) for n in names])


def compare(name: str, case: Case, names: list[str], got, recorded: dict) -> None:
    """Assert ``got`` (rows of floats) equals the recorded rows within the case's tolerances, naming the case, the
    output and the step of the largest difference."""
    assert names == recorded["outputs"], \
        f"{name}: outputs {[n for n in names if n not in recorded['outputs']]} are new, " \
        f"{[n for n in recorded['outputs'] if n not in names]} gone, or the order changed"
    want = np.array([[float(v) for v in row] for row in recorded["rows"]])
    got = np.array(got)
    assert got.shape == want.shape, f"{name}: {got.shape} steps x outputs, recorded {want.shape}"
    scale = np.maximum(np.abs(want).max(axis=0), 1e-300)
    allowed = tolerances(case, names)
    excess = np.abs(got - want) / scale - allowed
    worst = float(excess.max())
    assert worst <= 0.0, "".join(
        f"\n{name}: {names[j]} differs from the record at step {i} by {abs(got[i, j] - want[i, j]) / scale[j]:.3g} "
        f"of its scale {scale[j]:.6g} (tolerance {allowed[j]:g}): {float(got[i, j])!r}, recorded "
        f"{float(want[i, j])!r}" for j in np.flatnonzero((excess > 0.0).any(axis=0))[:6]
        for i in [int(np.argmax(excess[:, j]))])


@pytest.fixture(scope="module")
def record() -> dict:
    return json.loads(DATA.read_text())


@pytest.fixture(scope="module")
def fmus(contact_variants, eight_contacts, tmp_path_factory) -> dict:
    """``(fmi, contacts)`` -> (unzipped folder, model description) of the test run's builds."""
    from fmpy import extract, read_model_description

    paths = {(2, 1): contact_variants[2] / "RollingContact3D.fmu", (3, 1): contact_variants[3] / "RollingContact3D.fmu",
             (2, 8): eight_contacts[2] / "RollingContact3D_8.fmu"}
    unzipped = {key: Path(extract(str(path), unzipdir=tmp_path_factory.mktemp(f"fingerprint3d_{key[0]}_{key[1]}")))
                for key, path in paths.items()}
    return {key: (folder, read_model_description(str(folder))) for key, folder in unzipped.items()}


def test_the_record_holds_every_case(record):
    assert sorted(record) == sorted(CASES), \
        f"record and cases differ: {sorted(set(record) ^ set(CASES))} (python {DATA.name} --record)"


@pytest.mark.parametrize("name", list(CASES))
def test_outputs_equal_the_recorded_fingerprint(name, fmus, record):
    case = CASES[name]
    names, rows = run(*fmus[2, case.contacts], name, case)
    compare(name, case, names, rows, record[name])


@pytest.mark.parametrize("name", FMI3_TWINS)
def test_fmi3_outputs_equal_the_fmi2_twin_and_its_record(name, fmus, record):
    """The FMI 3.0 FMU against the FMI 2.0 FMU's run of the case bit for bit, and against its record."""
    case = CASES[name]
    names, two = run(*fmus[2, 1], name, case)
    three = run3(*fmus[3, 1], f"fmi3_{name}", case, names)
    differ = [(n, names[j], three[n][j], two[n][j]) for n in range(case.steps) for j in range(len(names))
              if three[n][j] != two[n][j]]
    assert not differ, "".join(f"\nFMI 3.0 {name}: step {n} {output} {a!r} != FMI 2.0's {b!r}"
                               for n, output, a, b in differ[:6])
    compare(f"FMI 3.0 {name}", case, names, three, record[name])


def recorded_json(data: dict) -> str:
    """The record as JSON with one step's outputs per line."""
    cases = []
    for name, (names, rows) in data.items():
        body = ",\n".join(json.dumps([repr(v) for v in row]) for row in rows)
        cases.append(f"{json.dumps(name)}: {{\n\"outputs\": {json.dumps(names)},\n\"rows\": [\n{body}\n]}}")
    return "{\n" + ",\n".join(cases) + "\n}\n"


def main(dest: Path | None = None) -> dict:
    """Build RollingContact3D and RollingContact3D_8 (FMI 2.0) into a temporary folder and run every case."""
    import subprocess
    import tempfile

    from fmpy import extract, read_model_description

    root = Path(__file__).resolve().parents[2]
    dest = Path(tempfile.mkdtemp()) if dest is None else dest
    for contacts in (1, 8):
        subprocess.run([sys.executable, str(root / "build_fmu.py"), "--contacts", str(contacts), "--dest", str(dest)],
                       check=True, capture_output=True)
    fmus = {}
    for contacts in (1, 8):
        unzipped = extract(str(dest / ("RollingContact3D.fmu" if contacts == 1 else "RollingContact3D_8.fmu")))
        fmus[contacts] = (unzipped, read_model_description(unzipped))
    return {name: run(*fmus[case.contacts], name, case) for name, case in CASES.items()}


if __name__ == "__main__" and sys.argv[1:] == ["--record"]:
    DATA.write_text(recorded_json(main()))
    print(f"wrote {DATA}")
