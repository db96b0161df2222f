"""Every output of every step is a function of the parameters, the inputs, the step times and the state: the same run
through fmpy gives the same bits however fast the machine solves (the table on auto, whose build is spread over the
exact steps by modelled work, not by the clock)."""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from fmpy import simulate_fmu

from rollcontact.line import dispatch

STEPS, H = 4000, 1e-3
PARAMETERS = {"friction_law": 1, "friction_coefficient": 0.3, "friction_kinetic_ratio": 0.6,
              "friction_decay": math.log(2.0) / 0.1, "contact_width": 0.01}


def signals() -> np.ndarray:
    """N 3.1e4 N with 5 % and the creep 1e-3 with 80 % oscillation at V 45 m/s, a new value at every step."""
    t = np.arange(STEPS + 1) * H
    rows = np.zeros(t.size, dtype=[("time", float), ("normal_load", float), ("creep", float), ("velocity", float)])
    rows["time"] = t
    rows["normal_load"] = 3.1e4 * (1.0 + 0.05 * np.sin(2.0 * np.pi * 7.0 * t))
    rows["creep"] = 1e-3 * (1.0 + 0.8 * np.sin(2.0 * np.pi * 3.0 * t + 0.3))
    rows["velocity"] = 45.0
    return rows


def run(unzipped) -> np.ndarray:
    result = simulate_fmu(str(unzipped), validate=False, stop_time=STEPS * H, output_interval=H, input=signals(),
                          start_values=PARAMETERS, output=["tangential_force", "stick_half_width",
                                                           "creep_stiffness", "method_used"])
    return np.array(result.tolist())


def test_the_same_run_gives_the_same_bits_on_a_slower_machine(unzipped, monkeypatch):
    first = run(unzipped)
    spec = dispatch.METHODS["polynomial"]
    delayed = []

    def slow(scene, **options):  # a machine (or a load) that makes every exact solve take 0.3 ms longer
        delayed.append(scene)
        time.sleep(3e-4)
        return spec.function(scene, **options)

    slow.options = spec.function.options
    monkeypatch.setitem(dispatch.METHODS, "polynomial", dataclasses.replace(spec, function=slow))
    slower = run(unzipped)
    assert len(delayed) > 500, f"the FMU's exact solves (steps and table build) ran delayed: {len(delayed)}"
    used = first[:, -1]
    assert (used == 6).sum() > STEPS / 2, f"the table answers most steps: method_used {np.unique(used)}"
    assert np.array_equal(first, slower), \
        f"outputs differ on {int((first != slower).any(axis=1).sum())} steps between the two runs"
