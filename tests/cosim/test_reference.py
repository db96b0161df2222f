"""Reference results: provenance, the CSV round trip, the band comparison, and the fmpy master's run of every scene
against its reference (a deliberate change of the physics leaves the band)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from rollcontact_cosim.reference import compare, read_reference, write_reference
from rollcontact_cosim.scenes import SCENE_NAMES, Band, load_cosim_scene


@pytest.mark.parametrize("name", SCENE_NAMES)
def test_reference_files_record_their_provenance(name):
    scene = load_cosim_scene(name)
    values, header = read_reference(scene.reference_path)
    for key in ("command", "rollcontact", "git_commit", "master", "algorithm", "step_size", "date", "band"):
        assert header.get(key), f"{scene.reference_path.name}: provenance lacks {key!r}: {header}"
    assert float(header["step_size"]) == scene.step_size, "the reference was made with the scene's step"
    assert header["algorithm"] == scene.algorithm, "the reference was made with the scene's algorithm"
    assert values.dtype.names == ("time", *scene.outputs), "the reference records the scene's outputs"
    assert values.size == scene.steps // scene.band.stride + 1, "one row per stride communication points"


def test_reference_round_trip_and_band(tmp_path):
    t = np.linspace(0.0, 1.0, 201)
    values = np.empty(t.size, dtype=[("time", float), ("y", float)])
    values["time"], values["y"] = t, np.sin(2 * np.pi * 3 * t) + 0.1 / 3
    path = write_reference(tmp_path / "x_ref.csv", values, {"what": "test", "note": "a: b"})
    again, header = read_reference(path)
    assert header == {"what": "test", "note": "a: b"}, f"provenance must round-trip: {header}"
    assert_allclose(again["y"], values["y"], rtol=1e-11, atol=1e-14, err_msg="12 significant digits")
    band = Band(("y",))
    assert compare(again, values, band) == [], "a result equal to its reference passes"
    shifted = values.copy()
    shifted["y"] = values["y"] * 1.03
    assert compare(shifted, values, band), "a 3 % change must leave the 1 % band"



@pytest.mark.parametrize("name", SCENE_NAMES)
def test_scene_matches_its_reference(run, name):
    scene = load_cosim_scene(name)
    result = run(name)
    reference, header = read_reference(scene.reference_path)
    problems = compare(result.values, reference, scene.band)
    assert not problems, f"{name} against {scene.reference_path.name} ({header.get('date')}): {problems}"


@pytest.mark.parametrize("name, change", [
    ("carter_sanity", {"friction_coefficient": 0.3 * 1.05}),
    ("carter_sanity", {"poisson_ratio": 0.30}),
    ("traction_ramp", {"friction_coefficient": 0.35 * 1.05}),
    ("corrugated_rail", {"corrugation_amplitude": 25e-6}),
    ("oscillating_torque", {"transient": 0}),
])
def test_a_deliberate_change_of_the_physics_fails_the_reference(run, name, change):
    scene = load_cosim_scene(name)
    reference, _ = read_reference(scene.reference_path)
    problems = compare(run(name, contact=change).values, reference, scene.band)
    assert problems, f"{name} with {change} must leave the reference band"
