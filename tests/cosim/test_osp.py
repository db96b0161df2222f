"""The libcosim master (rollcontact_cosim.osp): the system structure it writes from a scene's description, and its
runs against the fmpy master and the reference results, every wheel rig scene (the wheelset's in
``wheelset/test_cosim.py``).

Both masters run the same FMUs in this process with the same Jacobi algorithm and macro step and record the same
rows (libcosim's observer samples the contact one step later; osp shifts it back).  They make the same FMU calls
with the same values except for the time: libcosim counts integer nanoseconds, so the FMUs see
``(t0_ns + k H_ns) / 1e9``, which can differ from fmpy's ``t_0 + k H`` in the last bit.  The time-dependent motor
torque then differs by ~1e-16 relative, which the iterative contact solvers amplify to at most ~3e-9 of a
variable's range (measured: ~2e-10 in traction_ramp around the adhesion maximum, ~2e-13 elsewhere; 3e-9 with an
earlier, slower slip iteration).  :data:`MASTER_RTOL` = 1e-7 keeps a margin of 30 over that, while rows shifted by
one step differ by at least 9e-3 of some variable's range in every scene.  Against the references (made by the
fmpy master with Gauss-Seidel) libcosim's Jacobi differs mainly in the first macro step, where the host integrates
with the contact's start values; the scenes' bands allow 1 % outliers.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

pytest.importorskip("libcosimpy", reason="libcosimpy is not installed (pip install -e '.[test]' installs it)")

from rollcontact_cosim.master import run_cosimulation  # noqa: E402
from rollcontact_cosim.osp import NAMESPACE, OSP_CONFIG, run_osp, system_structure  # noqa: E402
from rollcontact_cosim.reference import compare, read_reference  # noqa: E402
from rollcontact_cosim.scenes import CONTACT, HOST, SCENE_NAMES, WHEEL_RIG, load_cosim_scene  # noqa: E402

MASTER_RTOL = 1e-7
"""Largest libcosim - fmpy difference of a recorded variable over its range (module docstring)."""


@pytest.fixture(scope="module", params=SCENE_NAMES)
def runs(request, fmu_dir, run):
    """(scene, libcosim result, fmpy Jacobi result) of one scene, run once for the module."""
    scene = load_cosim_scene(request.param)
    return scene, run_osp(scene, fmu_dir=fmu_dir), run(request.param, algorithm="jacobi")


def test_the_static_system_structure_is_the_wheel_rig_description():
    """models/cosim/OspSystemStructure.xml (for libcosim's own tools) is what system_structure writes of the wheel
    rig's description: both FMUs of models/ under their instance names, every connection, force_lag = 1."""
    written = system_structure(WHEEL_RIG, {name: f"../{name}.fmu" for name in (HOST, CONTACT)}, 0.0, 1e-3,
                               {HOST: {"force_lag": 1}})
    assert ET.canonicalize(ET.tostring(written.getroot()), strip_text=True) == \
        ET.canonicalize(from_file=str(OSP_CONFIG), strip_text=True), f"{OSP_CONFIG} is not the description's"


def test_the_system_structure_holds_every_connection_of_the_description():
    system = load_cosim_scene("wheelset_hunting").system
    root = system_structure(system, {"Wheelset": "file:///a/Wheelset.fmu",
                                     "RollingContact3D": "file:///a/RollingContact3D_2.fmu"}, 0.0, 2e-3).getroot()
    ns = {"osp": NAMESPACE}
    assert root.find("osp:BaseStepSize", ns).text == "0.002" and root.find("osp:Algorithm", ns).text == "fixedStep"
    sources = {s.get("name"): s.get("source") for s in root.findall("osp:Simulators/osp:Simulator", ns)}
    assert sources == {"Wheelset": "file:///a/Wheelset.fmu", "RollingContact3D": "file:///a/RollingContact3D_2.fmu"}
    connections = [tuple(f"{v.get('simulator')}.{v.get('name')}" for v in c.findall("osp:Variable", ns))
                   for c in root.findall("osp:Connections/osp:VariableConnection", ns)]
    assert connections == list(system.connections), "every connection, the Jacobians' too, in the description's order"


def test_libcosim_equals_fmpy_jacobi(runs):
    scene, osp, fmpy = runs
    assert osp.success and fmpy.success, (osp.message, fmpy.message)
    assert (osp.master, osp.algorithm, osp.steps) == ("libcosim", "jacobi", scene.steps)
    assert osp.values.dtype == fmpy.values.dtype
    assert osp.values.shape == fmpy.values.shape == (scene.steps + 1,)
    np.testing.assert_array_equal(osp.values["time"], fmpy.values["time"])
    for name in scene.outputs:
        expected, got = fmpy.values[name], osp.values[name]
        scale = max(np.ptp(expected), np.max(np.abs(expected)))
        assert scale > 0.0, f"{scene.name}: {name} is 0 throughout, the comparison would prove nothing"
        error = np.max(np.abs(got - expected)) / scale
        assert error <= MASTER_RTOL, f"{scene.name}: {name} differs by {error:.3g} of its range (row " \
                                     f"{np.argmax(np.abs(got - expected))})"


def test_libcosim_within_reference_band(runs):
    scene, osp, _ = runs
    reference, header = read_reference(scene.reference_path)
    problems = compare(osp.values, reference, scene.band)
    assert not problems, f"{scene.name} (reference by the {header.get('master')} master, " \
                         f"{header.get('algorithm')}): {problems}"


def test_parameter_overrides_reach_the_fmus(fmu_dir):
    """``host``/``contact`` override the scene's parameters in both masters alike (short run, through the
    dispatcher of rollcontact_cosim.master)."""
    options = dict(stop_time=0.02, host={"static_load": 50e3}, contact={"friction_coefficient": 0.25})
    osp = run_cosimulation("carter_sanity", master="libcosim", fmu_dir=fmu_dir, **options)
    fmpy = run_cosimulation("carter_sanity", algorithm="jacobi", fmu_dir=fmu_dir, **options)
    assert osp.success and osp.master == "libcosim", osp.message
    np.testing.assert_array_equal(osp.values[f"{HOST}.normal_load"], 50e3)
    np.testing.assert_allclose(osp.values[f"{CONTACT}.tangential_force"], fmpy.values[f"{CONTACT}.tangential_force"],
                               rtol=MASTER_RTOL)


def test_refused_step_is_reported(fmu_dir):
    """A Discard ends the run with success False, the instance named and only complete rows."""
    result = run_osp("carter_sanity", stop_time=0.01, contact={"friction_coefficient": -1.0}, fmu_dir=fmu_dir)
    assert not result.success
    assert f"{CONTACT}: Step not complete" in result.message, result.message
    assert result.steps == 0 and result.values.size == 0, (result.steps, result.values)


def test_bad_requests_are_refused():
    with pytest.raises(ValueError, match="Jacobi"):
        run_osp("carter_sanity", algorithm="gauss-seidel")
    with pytest.raises(ValueError, match="nanoseconds"):
        run_osp("carter_sanity", step_size=1.5e-9, stop_time=3e-9)

