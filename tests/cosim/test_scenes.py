"""Scene files and their system description: the wheel rig scenes' default system, the wheelset scene's system
with its Jacobian couplings, and the refusals that name the file, the key, the value and the limit."""

from __future__ import annotations

import dataclasses

import pytest

from rollcontact_cosim.scenes import (
    CONTACT,
    HOST,
    SCENE_NAMES,
    WHEEL_RIG,
    CosimSceneError,
    Instance,
    load_cosim_scene,
)
from rollcontact_cosim.wheelset import WheelsetParameters
from rollcontact_cosim.wheelset.cosim import contact_parameters, host_parameters

WHEELSET_SYSTEM = """[system]
host = "Wheelset"
contact = "RollingContact3D"
contacts = 2
to_contact = ["normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity"]
to_host = ["longitudinal_force", "lateral_force", "spin_moment", "dFx_dxi"]
"""
RUN = "[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['Wheelset.yaw_angle']\n"


@pytest.mark.parametrize("name", SCENE_NAMES)
def test_the_wheel_rig_scenes_are_the_wheel_rig_system_with_their_parameters(name):
    scene = load_cosim_scene(name)
    system = scene.system
    assert (system.host.name, system.contact.name) == (HOST, CONTACT), "instance names are the model names"
    assert (system.to_contact, system.to_host, system.fmi_version, system.integer_codes) == \
        (WHEEL_RIG.to_contact, WHEEL_RIG.to_host, 2, False), "a scene without [system] is the wheel rig's"
    assert system.connections == (
        ("WheelRig.normal_load", "RollingContact2D.normal_load"), ("WheelRig.creep", "RollingContact2D.creep"),
        ("WheelRig.velocity", "RollingContact2D.velocity"),
        ("RollingContact2D.tangential_force", "WheelRig.tangential_force"),
        ("RollingContact2D.creep_stiffness", "WheelRig.creep_stiffness")), system.connections
    assert system.instances == (system.contact, system.host), "Gauss-Seidel order: the contact first"
    assert scene.host_parameters("jacobi")["force_lag"] == 1 and scene.host_parameters("gauss-seidel")["force_lag"] == 0
    assert scene.contact_parameters() == dict(system.contact.parameters)


def test_the_wheelset_scene_couples_the_two_contacts_with_their_jacobians():
    scene = load_cosim_scene("wheelset_hunting")
    system = scene.system
    assert (system.host.fmu_name, system.contact.fmu_name) == ("Wheelset", "RollingContact3D_2")
    assert (system.host.build_selection, system.contact.build_selection) == (("--only", "Wheelset"),
                                                                              ("--contacts", "2"))
    connections = set(system.connections)
    assert len(connections) == len(system.connections) == 2 * (5 + 3 + 9), "per contact: 5 in, 3 forces, 9 slopes"
    for k in (1, 2):
        assert (f"Wheelset.spin[{k}]", f"RollingContact3D.spin[{k}]") in connections
        assert (f"RollingContact3D.dMz_deta[{k}]", f"Wheelset.dMz_deta[{k}]") in connections, "the Jacobian couples"
    p = WheelsetParameters()
    assert scene.contact_parameters() == contact_parameters(p), "the scene's contact is contact_parameters' default"
    defaults = host_parameters(p)
    assert all(defaults[name] == value for name, value in scene.host_parameters().items() if name != "force_lag"), \
        "the scene's host is the default wheelset"
    assert system.folder("m").as_posix() == "m" and \
        system.variant(integer_codes=True).folder("m").as_posix() == "m/integer_codes"
    with pytest.raises(ValueError, match="declares each per-contact variable as one array"):
        system.variant(fmi_version=3)


def test_an_instance_names_its_fmu_and_build():
    assert Instance("RollingContact2D", "RollingContact2D").fmu_name == "RollingContact2D"
    variant = Instance("RollingContact3D", "RollingContact3D", contacts=8)
    assert (variant.fmu_name, variant.build_selection) == ("RollingContact3D_8", ("--contacts", "8"))
    assert variant.names("inputs")[:2] == ("normal_load[1]", "longitudinal_creep[1]")
    assert len(variant.names("inputs")) == 8 * 5
    assert dataclasses.replace(WHEEL_RIG, fmi_version=3).folder("m").as_posix() == "m/fmi3"


@pytest.mark.parametrize("text, message", [
    ("[run]\nstop_time = 1.0\nstep_size = 0.3\noutputs = ['WheelRig.creep']\n", "whole number of macro steps"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creeep']\n", "WheelRig has no output 'creeep'"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creep']\n[host]\nmass = 1.0\n",
     "WheelRig has no parameter 'mass' (parameters: wheel_radius"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creep']\n[contact]\nfriction_law = 1.0\n",
     "friction_law = 1.0 must be of type int"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\noutputs = ['WheelRig.creep']\n[contact]\npoisson_ratio = 0.6\n",
     "[contact]: poisson_ratio = 0.6 is out of range"),
    ("[run]\nstop_time = 1.0\nstep_size = 0.1\nalgorithm = 'euler'\noutputs = ['WheelRig.creep']\n",
     "algorithm = 'euler' is unknown: use one of gauss-seidel, jacobi"),
    ('[system]\nhost = "Wheelset"\n' + RUN, "[system] contact is missing"),
    (WHEELSET_SYSTEM.replace('"Wheelset"', '"Bogie"') + RUN, "host = 'Bogie' is not a model: use one of WheelRig"),
    (WHEELSET_SYSTEM.replace("contacts = 2", "contacts = 3") + RUN,
     "[system] to_contact: Wheelset has no output 'normal_load[3]'"),
    (WHEELSET_SYSTEM.replace('"dFx_dxi"', '"dFx_dpsi"') + RUN, "RollingContact3D has no output 'dFx_dpsi[1]'"),
    (WHEELSET_SYSTEM.replace('"RollingContact3D"', '"RollingContact2D"') + RUN,
     "contacts = 2 is out of range: it must be 1, or >= 2 for a contact model built with several contacts"),
    (WHEELSET_SYSTEM + "fmi_version = 3\n" + RUN, "declares each per-contact variable as one array"),
    (WHEELSET_SYSTEM + "integer_codes = 1\n" + RUN, "integer_codes = 1 must be true or false"),
    (WHEELSET_SYSTEM + RUN + '[contact]\n"curvature_lateral[3]" = 1.0\n',
     "RollingContact3D has no parameter 'curvature_lateral[3]'"),
    (WHEELSET_SYSTEM + RUN + '[contact]\n"curvature_lateral[2]" = -1.0\n', "[contact]: curvature_lateral"),
    (WHEELSET_SYSTEM + RUN + "[host]\nspeed = -1.0\n", "[host]: speed = -1.0 m/s is out of range"),
    (WHEELSET_SYSTEM + RUN.replace("Wheelset.yaw_angle", "RollingContact3D.spin_moment"),
     "RollingContact3D has no output 'spin_moment'"),
])
def test_bad_scene_files_are_refused_with_the_reason(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(CosimSceneError, match="bad.toml") as caught:
        load_cosim_scene(path)
    assert message in str(caught.value), f"error {caught.value} should say {message!r}"
