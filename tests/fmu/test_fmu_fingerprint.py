"""A fixed input signal through the FMU, for each method and transient mode, against recorded outputs.

``tests/data/fmu_fingerprint.json`` holds every output of every step as ``repr`` strings, written by
``python tests/test_fmu_fingerprint.py --record``.  A refactoring must leave them bit for bit: the paths that are
pure floating-point arithmetic in Python (closed form, relaxation lag) are compared exactly; the steady paths through
LAPACK/BLAS (polynomial, discretised) to 1e-12 of each output's scale, because another CPU may take another BLAS
kernel with another rounding; the discretised transients to 1e-6 of it, because they iterate every substep to their
iteration tolerance (``rollcontact.line.halfspace.grid.ITERATION_TOLERANCE``, 1e-9) and carry the state over the run, so
another kernel's rounding moves each substep within that tolerance and the differences add up over the run's
substeps.  On one machine every path repeats bit for bit (``tests/stepping/test_table.py``, the runs with delays).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parent / "data" / "fmu_fingerprint.json"
H = 2e-3
STEPS = 24

# name: (parameters, tolerance) -- tolerance relative to each output's scale, 0: bit for bit (module docstring)
BITS, KERNEL, ITERATED = 0.0, 1e-12, 1e-6
CASES = {
    "closed_form_auto": ({}, BITS),
    "closed_form_explicit": ({"method": 1}, BITS),
    "polynomial_flat": ({"method": 2}, KERNEL),
    "discretised_flat": ({"method": 3, "elements": 60}, KERNEL),
    "corrugated_auto": ({"corrugation_amplitude": 2e-5, "corrugation_wavelength": 0.04}, KERNEL),
    "corrugated_tolerance": ({"corrugation_amplitude": 2e-5, "corrugation_wavelength": 0.04, "tolerance": 1e-3},
                             KERNEL),
    "falling_friction_auto": ({"friction_law": 1}, KERNEL),
    "falling_friction_tolerance": ({"friction_law": 1, "tolerance": 1e-3}, KERNEL),
    "relaxation_always": ({"transient": 2}, BITS),
    "relaxation_auto": ({"transient": 1}, BITS),
    "transient_always": ({"transient": 2, "method": 3, "elements": 40}, ITERATED),
    "transient_auto_tolerance": ({"transient": 1, "tolerance": 3e-3, "elements": 40}, ITERATED),
    "discretised_transient_auto": ({"transient": 1, "method": 3, "elements": 40, "tolerance": 1e-2}, ITERATED),
}


def signal(n: int) -> tuple[float, float, float]:
    """Load [N], creep [1] and speed [m/s] of step n: fast oscillations, so the instationary modes switch in."""
    load = 2.0e4 * (1.0 + 0.3 * math.sin(0.7 * n))
    creep = 1.5e-3 * math.sin(0.9 * n) + 4e-4 * n / STEPS
    speed = 20.0 + 2.0 * math.cos(0.5 * n)
    return load, creep, speed


def run(unzipped, description, name: str, parameters: dict) -> list[list[float]]:
    from fmpy.fmi2 import FMU2Slave

    variables = {v.name: v for v in description.modelVariables}
    fmu = FMU2Slave(guid=description.guid, unzipDirectory=str(unzipped),
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName=name)
    fmu.instantiate()
    for key, value in parameters.items():
        v = variables[key]
        (fmu.setReal if v.type == "Real" else fmu.setInteger)([v.valueReference], [value])
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    inputs = [variables[n].valueReference for n in ("normal_load", "creep", "velocity")]
    outputs = [v for v in description.modelVariables if v.causality == "output"]
    rows = []
    try:
        for n in range(STEPS):
            fmu.setReal(inputs, list(signal(n)))
            fmu.doStep(n * H, H)
            rows.append([float(fmu.getReal([v.valueReference])[0]) if v.type == "Real"
                         else float(fmu.getInteger([v.valueReference])[0]) for v in outputs])
    finally:
        fmu.terminate()
        fmu.freeInstance()
    return rows


@pytest.mark.parametrize("name", sorted(CASES))
def test_outputs_equal_the_recorded_fingerprint(name, unzipped, description):
    recorded = json.loads(DATA.read_text())[name]
    parameters, tolerance = CASES[name]
    got = np.array(run(unzipped, description, name, parameters))
    want = np.array([[float(v) for v in row] for row in recorded])
    assert got.shape == want.shape, f"{name}: {got.shape} outputs, recorded {want.shape}"
    if tolerance == BITS:
        assert np.array_equal(got, want), f"{name}: outputs differ from the recorded ones bit for bit"
    else:
        scale = np.maximum(np.abs(want).max(axis=0), 1e-300)
        worst = float(np.max(np.abs(got - want) / scale))
        assert worst <= tolerance, f"{name}: outputs differ from the recorded ones by {worst:.3g} of their scale"


if __name__ == "__main__" and sys.argv[1:] == ["--record"]:
    import subprocess
    import tempfile

    from fmpy import extract, read_model_description

    root = Path(__file__).resolve().parents[2]
    dest = Path(tempfile.mkdtemp())
    subprocess.run([sys.executable, str(root / "build_fmu.py"), "--dest", str(dest)], check=True)
    unzipped = extract(str(dest / "RollingContact2D.fmu"))
    description = read_model_description(unzipped)
    data = {name: [[repr(v) for v in row] for row in run(unzipped, description, name, parameters)]
            for name, (parameters, _) in sorted(CASES.items())}
    DATA.write_text(json.dumps(data, indent=0) + "\n")
    print(f"wrote {DATA}")
