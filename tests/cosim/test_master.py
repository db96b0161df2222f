"""The fmpy master on the wheel rig scenes: Jacobi against Gauss-Seidel, the row convention against Carter and
Hertz, the adhesion maximum of the traction ramp, refusals and their reasons, the FMUs taken as they are.

Tolerances: identities and closed forms ~1e-12, the host's quasi-static equilibrium 1e-4, the orderings against
each other within the scene's band (1 % of a variable's range, 5 of 1000 resampled points, 1 % outliers)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from rollcontact.core.materials import Material
from rollcontact.line.carter import carter
from rollcontact.line.hertz import hertz
from rollcontact_cosim.master import run_cosimulation, summarise
from rollcontact_cosim.reference import compare
from rollcontact_cosim.scenes import CONTACT, HOST, SCENE_NAMES, load_cosim_scene

CREEP, TRACTION, FORCE = f"{HOST}.creep", f"{CONTACT}.traction_coefficient", f"{CONTACT}.tangential_force"


@pytest.mark.parametrize("name", SCENE_NAMES)
def test_jacobi_agrees_with_gauss_seidel(run, name):
    """With force_lag following the algorithm both orderings stay within the band at the scene's step."""
    scene = load_cosim_scene(name)
    gauss_seidel, jacobi = run(name, algorithm="gauss-seidel"), run(name, algorithm="jacobi")
    assert jacobi.algorithm == "jacobi" and gauss_seidel.algorithm == "gauss-seidel", "algorithms as requested"
    assert not np.array_equal(jacobi.values[FORCE], gauss_seidel.values[FORCE]), "the two orderings differ at all"
    problems = compare(jacobi.values, gauss_seidel.values, scene.band)
    assert not problems, f"{name}: Jacobi leaves the band of Gauss-Seidel: {problems}"



def test_carter_sanity_is_hertz_and_carter(run):
    """Row k pairs the contact's outputs with the creep they were evaluated at: T = Carter(xi), a = Hertz; the
    steady creep is the host's quasi-static one."""
    values = run("carter_sanity").values
    n_per_length = 98.1e3 / 0.02
    modulus = Material(210e9, 0.28).contact_modulus
    expected = np.array([carter(n_per_length, xi, 0.46, modulus, 0.3)[0] * 0.02 for xi in values[CREEP]])
    assert_allclose(values[FORCE], expected, rtol=1e-12, atol=1e-9, err_msg="T = Carter(xi) row by row")
    assert_allclose(values[f"{CONTACT}.contact_half_width"], hertz(n_per_length, 0.46, modulus)[0], rtol=1e-12,
                    err_msg="a = Hertz")
    v, xi = values[f"{HOST}.velocity"][-1], values[CREEP][-1]
    resistance = 100.0 + 5.0 * v + 0.5 * v * v
    # quasi-static: J omega' = M - r T and m v' = T - F_res with omega' r = (1 + xi) v'
    force = (7.25e3 + 150.0 * (1.0 + xi) * resistance / (1e4 * 0.46)) / (0.46 + 150.0 * (1.0 + xi) / (1e4 * 0.46))
    assert_allclose(values[FORCE][-1], force, rtol=1e-4, err_msg="steady traction of the torque balance")


def test_traction_ramp_passes_the_adhesion_maximum(run):
    result = run("traction_ramp")
    s = summarise(result)
    values = result.values
    assert 0.3 < s["peak_traction_coefficient"] < 0.35, f"peak adhesion below mu = 0.35: {s}"
    assert 2e-3 < s["creep_at_peak"] < 6e-3, f"peak near the Carter saturation creep mu a / R ~ 3.8e-3: {s}"
    assert values[CREEP][-1] > 0.03, f"beyond the maximum the wheel spins up to several % creep: {values[CREEP][-1]}"
    assert values[TRACTION][-1] < 0.8 * s["peak_traction_coefficient"], "falling friction lowers T/N after the peak"
    assert np.all(values[f"{CONTACT}.method_used"] == 2), "falling friction takes the polynomial method"


def test_a_refused_step_ends_the_run_with_the_reason(fmu_dir):
    result = run_cosimulation("carter_sanity", fmu_dir=fmu_dir, contact={"friction_coefficient": -1.0})
    assert not result.success, "a negative friction coefficient must stop the run"
    assert "RollingContact2D" in result.message and "friction_coefficient" in result.message, result.message
    assert result.values.size == 0 and result.steps == 0, "no complete row before the first refused step"



def test_unknown_override_is_refused_with_the_choices(fmu_dir):
    with pytest.raises(KeyError, match="WheelRig has no parameter 'mass' \\(choices: wheel_radius"):
        run_cosimulation("carter_sanity", fmu_dir=fmu_dir, host={"mass": 1e4})


def test_without_build_the_fmus_are_taken_as_they_are(fmu_dir, monkeypatch):
    """``build=False`` (a sweep's workers) runs no build_fmu.py, and a folder without the FMUs fails to load."""
    import rollcontact_cosim.fmus as fmus

    def no_build(*args, **kwargs):
        raise AssertionError(f"build_fmu.py was run: {args}")

    monkeypatch.setattr(fmus.subprocess, "run", no_build)
    assert run_cosimulation("carter_sanity", fmu_dir=fmu_dir, stop_time=0.01, build=False).success
    with pytest.raises(Exception, match="No such file"):
        run_cosimulation("carter_sanity", fmu_dir=fmu_dir / "nowhere", stop_time=0.01, build=False)
