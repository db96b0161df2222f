"""rollcontact_cosim: co-simulation of the RollingContact2D FMU with the WheelRig host FMU.

Modules: :mod:`~rollcontact_cosim.wheel_rig` (the host's physics, bundled in ``WheelRig.fmu``; no FMI),
:mod:`~rollcontact_cosim.scenes` (scene files ``models/cosim/<scene>.toml``), :mod:`~rollcontact_cosim.master`
(fixed-step fmpy master, FMU building), :mod:`~rollcontact_cosim.reference` (reference CSVs with provenance,
band comparison), :mod:`~rollcontact_cosim.stable_step` (largest stable macro step), ``python -m
rollcontact_cosim`` (main job).  This module imports nothing else: the WheelRig FMU imports
``rollcontact_cosim.wheel_rig`` in hosts that have neither fmpy nor matplotlib.
"""
